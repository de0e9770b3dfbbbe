#pragma once
/// \file
/// \brief LibusbTransport: UsbTransport over libusb-1.0 for an FTDI-bridged device (the Novint
/// Falcon). exchange() uses two asynchronous bulk transfers (OUT endpoint 0x02, IN endpoint 0x81)
/// allocated at open() and reused every period; it waits for completions with
/// libusb_handle_events_timeout_completed(), which allocates nothing once the device's poll set
/// is built. A transfer or submission reporting LIBUSB_ERROR_NO_DEVICE / LIBUSB_TRANSFER_NO_DEVICE
/// marks the device gone (hot unplug).
///
/// \todo #6 libusb's Linux backend callocs its URB array on every transfer submission, so each
/// exchange() makes one small C-heap allocation inside libusb (not operator new); removing it needs
/// usbfs URBs submitted directly.
///
/// Thread-safety: thread-bound (see UsbTransport); present() is thread-safe.

#include <array>
#include <atomic>
#include <cstdint>

#include "depthtouch/drivers/usb/usb_transport.h"

struct libusb_context;
struct libusb_device_handle;
struct libusb_transfer;

namespace depthtouch::drivers {

class LibusbTransport final : public UsbTransport {
public:
    LibusbTransport() = default;
    ~LibusbTransport() override;

    /// \return whether a device with these ids is on the bus (enumerates it; not real-time safe);
    /// false when libusb cannot start (no USB). Errors: Io (listing the devices failed).
    static Result<bool> probe(std::uint16_t vendorId, std::uint16_t productId);

    [[nodiscard]] Result<void> open(std::uint16_t vendorId, std::uint16_t productId) override;
    void close() noexcept override;
    [[nodiscard]] bool present() const noexcept override;
    [[nodiscard]] Result<void> control(FtdiRequest request, std::uint16_t value) override;
    [[nodiscard]] Result<std::size_t> write(const std::uint8_t *data, std::size_t size,
                                            platform::Duration timeout) override;
    [[nodiscard]] Result<std::size_t> read(std::uint8_t *data, std::size_t capacity,
                                           platform::Duration timeout) override;
    [[nodiscard]] Result<std::size_t> exchange(const std::uint8_t *out, std::size_t outSize,
                                               std::uint8_t *in, std::size_t inCapacity,
                                               platform::Duration timeout) noexcept override;

private:
    static void onTransferDone(libusb_transfer *transfer) noexcept;
    /// Cancels posted asynchronous transfers and waits (bounded) for their completion.
    void cancelAsync() noexcept;
    /// Handles libusb events for up to \a micros microseconds or until *completed is set.
    /// \return a libusb error code (0 on success).
    int handleEvents(long micros, int *completed) noexcept;
    Result<void> submitIn() noexcept;

    static constexpr std::size_t kMaxPacket = 64;

    libusb_context *ctx_ = nullptr;
    libusb_device_handle *handle_ = nullptr;
    libusb_transfer *out_ = nullptr;
    libusb_transfer *in_ = nullptr;
    std::array<std::uint8_t, kMaxPacket> outBuf_{};
    std::array<std::uint8_t, kMaxPacket> inBuf_{};
    bool claimed_ = false;
    int outBusy_ = 0;      ///< Non-zero while the OUT transfer is posted.
    int inBusy_ = 0;       ///< Non-zero while the IN transfer is posted.
    int inCompleted_ = 0;  ///< Set by the IN callback.
    int outCompleted_ = 0; ///< Set by the OUT callback.
    std::atomic<bool> gone_{true};
};

} // namespace depthtouch::drivers
