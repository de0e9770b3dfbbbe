#pragma once
/// \file
/// \brief UsbTransport: the few USB operations the Falcon driver needs from an FTDI serial bridge,
/// behind an interface so the whole driver runs against a device-side emulator (FakeFalcon) as well
/// as against libusb (LibusbTransport).
///
/// States: Closed --open()--> Open --(device gone)--> Gone; close() returns to Closed from any
/// state. Every call but open() and close() returns Errc::NoDevice once the device is gone.
///
/// Real-time: exchange() and present() are called from the haptic thread: they do not allocate,
/// lock (beyond what libusb's audited event handling does) or log, and wait at most the timeout
/// given. Every other call is for a non-real-time thread, and none runs concurrently with another.

#include <cstddef>
#include <cstdint>

#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/macros.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::drivers {

/// FTDI vendor requests (bRequest of an OUT vendor control transfer to the device, as used by the
/// FT232 family; wIndex selects the port, 0 for a single-port chip).
enum class FtdiRequest : std::uint8_t {
    Reset = 0x00,          ///< value: 0 reset the port, 1 purge RX, 2 purge TX.
    ModemControl = 0x01,   ///< value: (mask << 8) | state, bit 0 DTR, bit 1 RTS.
    FlowControl = 0x02,    ///< value 0: no flow control (handshake in the high byte of wIndex).
    BaudRate = 0x03,       ///< value: divisor of the 3 MHz base clock (low 14 bits + fraction).
    LineProperty = 0x04,   ///< value: data bits | parity << 8 | stop bits << 11.
    LatencyTimer = 0x09,   ///< value: milliseconds (1..255) before a partial packet is sent.
    BitMode = 0x0B,        ///< value: mode << 8 | pin mask; 0 = reset to serial (UART) mode.
};

/// \name FTDI request values used by the Falcon (public FTDI facts)
///@{
inline constexpr std::uint16_t kFtdiPurgeRx = 1;
inline constexpr std::uint16_t kFtdiPurgeTx = 2;
inline constexpr std::uint16_t kFtdiDtrHigh = 0x0101;
inline constexpr std::uint16_t kFtdiDtrLow = 0x0100;
inline constexpr std::uint16_t kFtdiRtsHigh = 0x0202;
inline constexpr std::uint16_t kFtdiRtsLow = 0x0200;
inline constexpr std::uint16_t kFtdiLine8N1 = 8;
inline constexpr std::uint16_t kFtdiBitModeReset = 0;
inline constexpr std::uint16_t kFtdiBaud9600 = 0x4138;    ///< 3 MHz / 312.5.
inline constexpr std::uint16_t kFtdiBaud140000 = 0x0015;  ///< 3 MHz / 21 (≈ 142.9 kBd).
inline constexpr std::uint16_t kFtdiBaud1456312 = 0x0002; ///< 3 MHz / 2 (the firmware's rate).
///@}

/// USB identity of the Novint Falcon (an FTDI FT232 with Novint's product id).
inline constexpr std::uint16_t kFalconVendorId = 0x0403;
inline constexpr std::uint16_t kFalconProductId = 0xCB48;

/// \brief The transport of bytes to and from an FTDI-bridged device.
class UsbTransport {
public:
    virtual ~UsbTransport() = default;

    /// \brief Opens the first device with \a vendorId / \a productId, claims its interface and
    /// preallocates what exchange() needs. Not real-time safe.
    /// \return Errors: NoDevice (absent), PermissionDenied (no access to the USB node), Busy
    /// (claimed by another program or driver), Io.
    [[nodiscard]] virtual Result<void> open(std::uint16_t vendorId, std::uint16_t productId) = 0;

    /// \brief Releases the device. Always allowed; no-op when closed.
    virtual void close() noexcept = 0;

    /// \return false once the device was unplugged (or never opened). Real-time safe.
    [[nodiscard]] virtual bool present() const noexcept = 0;

    /// \brief One FTDI vendor control transfer (no data stage). Not real-time safe.
    /// \return Errors: NoDevice, Io.
    [[nodiscard]] virtual Result<void> control(FtdiRequest request, std::uint16_t value) = 0;

    /// \brief Synchronous bulk write of \a size bytes. Not real-time safe.
    /// \return the bytes written. Errors: NoDevice, Timeout, Io.
    [[nodiscard]] virtual Result<std::size_t> write(const std::uint8_t *data, std::size_t size,
                                                    platform::Duration timeout) = 0;

    /// \brief Synchronous read of up to \a capacity payload bytes (FTDI status bytes removed),
    /// waiting until \a capacity bytes came or \a timeout passed. Not real-time safe.
    /// \return the bytes read (fewer than capacity at the timeout). Errors: NoDevice, Io.
    [[nodiscard]] virtual Result<std::size_t> read(std::uint8_t *data, std::size_t capacity,
                                                   platform::Duration timeout) = 0;

    /// \brief One servo-rate exchange with transfers allocated at open(): sends \a outSize bytes
    /// (skipped when the previous send has not completed yet), then waits up to \a timeout for
    /// payload bytes, copying at most \a inCapacity of them to \a in. Real-time safe.
    /// \return the payload bytes received (at least one). Errors: NoDevice (unplugged: present()
    /// becomes false), Timeout (nothing arrived in time; the receive stays posted for the next
    /// call), Io.
    [[nodiscard]] virtual Result<std::size_t> exchange(const std::uint8_t *out, std::size_t outSize,
                                                       std::uint8_t *in, std::size_t inCapacity,
                                                       platform::Duration timeout) noexcept = 0;

protected:
    UsbTransport() = default;
    DT_DISABLE_COPY_AND_MOVE(UsbTransport)
};

/// \brief Removes the two modem-status bytes an FTDI chip puts at the start of every
/// \a maxPacketSize-byte USB packet of a bulk IN transfer, in place.
/// \return the payload bytes left at the front of \a data.
std::size_t stripFtdiStatus(std::uint8_t *data, std::size_t size,
                            std::size_t maxPacketSize = 64) noexcept;

} // namespace depthtouch::drivers
