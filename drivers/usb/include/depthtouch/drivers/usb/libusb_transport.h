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
/// The libusb calls go through a LibusbApi table (the system's libusb-1.0 by default), so tests can
/// put a stand-in USB bus with a device on the other side; libusb_fill_bulk_transfer() (an inline
/// function of libusb.h) and libusb_strerror() (a table of strings) are called directly.
///
/// Thread-safety: thread-bound (see UsbTransport); present() is thread-safe.

#include <array>
#include <atomic>
#include <cstdint>

#include <sys/types.h>

#include "depthtouch/drivers/usb/usb_transport.h"

struct libusb_context;
struct libusb_device;
struct libusb_device_descriptor;
struct libusb_device_handle;
struct libusb_transfer;
struct timeval;

namespace depthtouch::drivers {

/// \brief The libusb-1.0 functions LibusbTransport calls, one pointer each, with libusb's own
/// signatures, arguments, return values and error codes (LIBUSB_ERROR_*; see libusb.h). A stand-in
/// must keep libusb's contracts: allocTransfer() returns a transfer freeTransfer() releases, a
/// submitted transfer completes exactly once (its callback runs inside handleEvents...(), which
/// sets *completed through the callback's effects), cancelTransfer() makes a posted transfer
/// complete with LIBUSB_TRANSFER_CANCELLED on a later event handling.
struct LibusbApi {
    int (*init)(libusb_context **ctx);
    void (*exit)(libusb_context *ctx);
    ssize_t (*getDeviceList)(libusb_context *ctx, libusb_device ***list);
    void (*freeDeviceList)(libusb_device **list, int unrefDevices);
    int (*getDeviceDescriptor)(libusb_device *dev, libusb_device_descriptor *desc);
    int (*open)(libusb_device *dev, libusb_device_handle **handle);
    void (*close)(libusb_device_handle *handle);
    int (*setAutoDetachKernelDriver)(libusb_device_handle *handle, int enable);
    int (*claimInterface)(libusb_device_handle *handle, int interfaceNumber);
    int (*releaseInterface)(libusb_device_handle *handle, int interfaceNumber);
    int (*controlTransfer)(libusb_device_handle *handle, std::uint8_t requestType,
                           std::uint8_t request, std::uint16_t value, std::uint16_t index,
                           unsigned char *data, std::uint16_t length, unsigned int timeoutMs);
    int (*bulkTransfer)(libusb_device_handle *handle, unsigned char endpoint, unsigned char *data,
                        int length, int *transferred, unsigned int timeoutMs);
    libusb_transfer *(*allocTransfer)(int isoPackets);
    void (*freeTransfer)(libusb_transfer *transfer);
    int (*submitTransfer)(libusb_transfer *transfer);
    int (*cancelTransfer)(libusb_transfer *transfer);
    int (*handleEventsTimeoutCompleted)(libusb_context *ctx, timeval *tv, int *completed);
};

/// \return the table of the system's libusb-1.0 (static storage).
[[nodiscard]] const LibusbApi &systemLibusb() noexcept;

class LibusbTransport final : public UsbTransport {
public:
    /// \param api The libusb functions to call; referenced, so it must outlive the transport.
    explicit LibusbTransport(const LibusbApi &api = systemLibusb()) noexcept : api_(&api) {}
    ~LibusbTransport() override;

    /// \return whether a device with these ids is on the bus (enumerates it through \a api; not
    /// real-time safe); false when libusb cannot start (no USB). Errors: listing the devices failed
    /// (Io, or NoDevice, PermissionDenied, Busy, Timeout for those libusb codes).
    static Result<bool> probe(std::uint16_t vendorId, std::uint16_t productId,
                              const LibusbApi &api = systemLibusb());

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
    /// \brief Posts the asynchronous bulk \a transfer of the first \a length bytes of \a buffer on
    /// \a endpoint (completion: onTransferDone() sets \a completed, cleared here); sets \a busy
    /// once posted. Real-time safe. \return Errors: the libusb code mapped with \a what as the text
    /// (a static string); NoDevice also marks the device gone.
    Result<void> submit(libusb_transfer *transfer, unsigned char endpoint, std::uint8_t *buffer,
                        std::size_t length, int &completed, int &busy, const char *what) noexcept;
    /// Posts the IN transfer into inBuf_ (submit()).
    Result<void> submitIn() noexcept;

    static constexpr std::size_t kMaxPacket = 64;

    const LibusbApi *api_;
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
