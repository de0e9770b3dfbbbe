#include "depthtouch/drivers/usb/libusb_transport.h"

#include <algorithm>
#include <chrono>
#include <cstring>

#include <libusb.h>

#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(Usb)

namespace depthtouch::drivers {

namespace {

constexpr unsigned char kEndpointOut = 0x02;
constexpr unsigned char kEndpointIn = 0x81;
constexpr std::uint8_t kVendorOut = 0x40; // LIBUSB_REQUEST_TYPE_VENDOR | RECIPIENT_DEVICE | OUT
constexpr unsigned kControlTimeoutMs = 1000;

Error libusbError(int code, const char *what) noexcept
{
    switch (code) {
    case LIBUSB_ERROR_NO_DEVICE:
    case LIBUSB_ERROR_NOT_FOUND:
        return Error{Errc::NoDevice, what};
    case LIBUSB_ERROR_ACCESS:
        return Error{Errc::PermissionDenied, what};
    case LIBUSB_ERROR_BUSY:
        return Error{Errc::Busy, what};
    case LIBUSB_ERROR_TIMEOUT:
        return Error{Errc::Timeout, what};
    default:
        return Error{Errc::Io, what};
    }
}

unsigned toMillis(platform::Duration d) noexcept
{
    const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(d).count();
    return static_cast<unsigned>(std::clamp<long long>(ms, 1, 60'000));
}

/// Finds and opens the first device with the ids. \return a libusb error code.
int openFirst(const LibusbApi &api, libusb_context *ctx, std::uint16_t vid, std::uint16_t pid,
              libusb_device_handle **handle, bool *found) noexcept
{
    libusb_device **list = nullptr;
    const ssize_t n = api.getDeviceList(ctx, &list);
    if (n < 0)
        return static_cast<int>(n);
    int rc = LIBUSB_ERROR_NO_DEVICE;
    *found = false;
    for (ssize_t i = 0; i < n; ++i) {
        libusb_device_descriptor desc{};
        if (api.getDeviceDescriptor(list[i], &desc) != 0 || desc.idVendor != vid ||
            desc.idProduct != pid)
            continue;
        *found = true;
        rc = handle != nullptr ? api.open(list[i], handle) : 0;
        break;
    }
    api.freeDeviceList(list, 1);
    return rc;
}

} // namespace

const LibusbApi &systemLibusb() noexcept
{
    static const LibusbApi api{
        .init = &libusb_init,
        .exit = &libusb_exit,
        .getDeviceList = &libusb_get_device_list,
        .freeDeviceList = &libusb_free_device_list,
        .getDeviceDescriptor = &libusb_get_device_descriptor,
        .open = &libusb_open,
        .close = &libusb_close,
        .setAutoDetachKernelDriver = &libusb_set_auto_detach_kernel_driver,
        .claimInterface = &libusb_claim_interface,
        .releaseInterface = &libusb_release_interface,
        .controlTransfer = &libusb_control_transfer,
        .bulkTransfer = &libusb_bulk_transfer,
        .allocTransfer = &libusb_alloc_transfer,
        .freeTransfer = &libusb_free_transfer,
        .submitTransfer = &libusb_submit_transfer,
        .cancelTransfer = &libusb_cancel_transfer,
        .handleEventsTimeoutCompleted = &libusb_handle_events_timeout_completed,
    };
    return api;
}

LibusbTransport::~LibusbTransport()
{
    close();
}

Result<bool> LibusbTransport::probe(std::uint16_t vendorId, std::uint16_t productId,
                                    const LibusbApi &api)
{
    libusb_context *ctx = nullptr;
    if (api.init(&ctx) != 0) // no USB on this system: no device either
        return false;
    bool found = false;
    const int rc = openFirst(api, ctx, vendorId, productId, nullptr, &found);
    api.exit(ctx);
    if (rc != 0 && rc != LIBUSB_ERROR_NO_DEVICE)
        return unexpected(libusbError(rc, "Failed to list USB devices"));
    return found;
}

Result<void> LibusbTransport::open(std::uint16_t vendorId, std::uint16_t productId)
{
    if (ctx_ != nullptr)
        return unexpected(Errc::InvalidState, "USB transport already open");
    if (api_->init(&ctx_) != 0) {
        ctx_ = nullptr;
        return unexpected(Errc::Io, "Failed to initialise libusb");
    }
    bool found = false;
    int rc = openFirst(*api_, ctx_, vendorId, productId, &handle_, &found);
    if (rc != 0 && !found && rc != LIBUSB_ERROR_NO_DEVICE) {
        DT_LOG(Usb, Error, "Failed to list USB devices: %s", libusb_strerror(rc));
        close();
        return unexpected(Errc::Io, "Failed to list USB devices");
    }
    if (rc != 0) {
        // Not on the bus is what every try of a device awaited by hot-plug finds: no error line.
        if (found)
            DT_LOG(Usb, Error, "Failed to open USB device %04x:%04x: %s", vendorId, productId,
                   libusb_strerror(rc));
        else
            DT_LOG(Usb, Debug, "USB device %04x:%04x not found", vendorId, productId);
        handle_ = nullptr;
        close();
        return unexpected(libusbError(found ? rc : LIBUSB_ERROR_NO_DEVICE,
                                      rc == LIBUSB_ERROR_ACCESS
                                          ? "No permission to open the USB device (udev rule?)"
                                          : "Failed to open the USB device"));
    }
    (void)api_->setAutoDetachKernelDriver(handle_, 1);
    rc = api_->claimInterface(handle_, 0);
    if (rc != 0) {
        DT_LOG(Usb, Error, "Failed to claim USB interface 0: %s", libusb_strerror(rc));
        close();
        return unexpected(libusbError(rc, "Failed to claim the USB interface"));
    }
    claimed_ = true;
    out_ = api_->allocTransfer(0);
    in_ = api_->allocTransfer(0);
    if (out_ == nullptr || in_ == nullptr) {
        close();
        return unexpected(Errc::OutOfResources, "Failed to allocate USB transfers");
    }
    gone_.store(false, std::memory_order_release);
    return ok();
}

void LibusbTransport::close() noexcept
{
    if (ctx_ == nullptr)
        return;
    cancelAsync();
    if (out_ != nullptr)
        api_->freeTransfer(out_);
    if (in_ != nullptr)
        api_->freeTransfer(in_);
    out_ = in_ = nullptr;
    if (handle_ != nullptr) {
        if (claimed_)
            (void)api_->releaseInterface(handle_, 0);
        api_->close(handle_);
    }
    claimed_ = false;
    handle_ = nullptr;
    api_->exit(ctx_);
    ctx_ = nullptr;
    gone_.store(true, std::memory_order_release);
}

bool LibusbTransport::present() const noexcept
{
    return !gone_.load(std::memory_order_acquire);
}

void LibusbTransport::onTransferDone(libusb_transfer *t) noexcept
{
    auto *self = static_cast<LibusbTransport *>(t->user_data);
    if (t->status == LIBUSB_TRANSFER_NO_DEVICE)
        self->gone_.store(true, std::memory_order_release);
    if (t == self->in_) {
        self->inBusy_ = 0;
        self->inCompleted_ = 1;
    } else {
        self->outBusy_ = 0;
        self->outCompleted_ = 1;
    }
}

int LibusbTransport::handleEvents(long micros, int *completed) noexcept
{
    timeval tv{};
    tv.tv_sec = micros / 1'000'000;
    tv.tv_usec = micros % 1'000'000;
    return api_->handleEventsTimeoutCompleted(ctx_, &tv, completed);
}

void LibusbTransport::cancelAsync() noexcept
{
    if (inBusy_ != 0)
        (void)api_->cancelTransfer(in_);
    if (outBusy_ != 0)
        (void)api_->cancelTransfer(out_);
    // Cancelled transfers complete on the next event handling; bounded wait (the device may be
    // gone).
    for (int i = 0; i < 100 && (inBusy_ != 0 || outBusy_ != 0); ++i)
        (void)handleEvents(10'000, inBusy_ != 0 ? &inCompleted_ : &outCompleted_);
    inBusy_ = outBusy_ = 0;
}

Result<void> LibusbTransport::control(FtdiRequest request, std::uint16_t value)
{
    if (!present())
        return unexpected(Errc::NoDevice, "USB device gone");
    const int rc = api_->controlTransfer(handle_, kVendorOut, static_cast<std::uint8_t>(request),
                                         value, 0, nullptr, 0, kControlTimeoutMs);
    if (rc < 0) {
        if (rc == LIBUSB_ERROR_NO_DEVICE)
            gone_.store(true, std::memory_order_release);
        DT_LOG(Usb, Error, "Failed to send FTDI request %u (value 0x%04x): %s",
               static_cast<unsigned>(request), value, libusb_strerror(rc));
        return unexpected(libusbError(rc, "FTDI control request failed"));
    }
    return ok();
}

Result<std::size_t> LibusbTransport::write(const std::uint8_t *data, std::size_t size,
                                           platform::Duration timeout)
{
    if (!present())
        return unexpected(Errc::NoDevice, "USB device gone");
    cancelAsync();
    int done = 0;
    // libusb takes a non-const buffer for both directions; an OUT transfer only reads it.
    const int rc = api_->bulkTransfer(handle_, kEndpointOut, const_cast<std::uint8_t *>(data),
                                      static_cast<int>(size), &done, toMillis(timeout));
    if (rc != 0) {
        if (rc == LIBUSB_ERROR_NO_DEVICE)
            gone_.store(true, std::memory_order_release);
        return unexpected(libusbError(rc, "USB bulk write failed"));
    }
    return static_cast<std::size_t>(done);
}

Result<std::size_t> LibusbTransport::read(std::uint8_t *data, std::size_t capacity,
                                          platform::Duration timeout)
{
    if (!present())
        return unexpected(Errc::NoDevice, "USB device gone");
    cancelAsync();
    platform::Clock &clock = platform::SteadyClock::instance();
    const platform::TimePoint deadline = clock.now() + timeout;
    std::size_t got = 0;
    std::array<std::uint8_t, kMaxPacket> buf{};
    while (got < capacity) {
        const platform::Duration left = deadline - clock.now();
        if (left <= platform::Duration::zero())
            break;
        int n = 0;
        const int rc = api_->bulkTransfer(handle_, kEndpointIn, buf.data(),
                                          static_cast<int>(buf.size()), &n, toMillis(left));
        if (rc == LIBUSB_ERROR_TIMEOUT)
            break;
        if (rc != 0) {
            if (rc == LIBUSB_ERROR_NO_DEVICE)
                gone_.store(true, std::memory_order_release);
            return unexpected(libusbError(rc, "USB bulk read failed"));
        }
        const std::size_t payload = stripFtdiStatus(buf.data(), static_cast<std::size_t>(n));
        const std::size_t take = std::min(payload, capacity - got);
        std::memcpy(data + got, buf.data(), take);
        got += take;
    }
    return got;
}

Result<void> LibusbTransport::submit(libusb_transfer *transfer, unsigned char endpoint,
                                     std::uint8_t *buffer, std::size_t length, int &completed,
                                     int &busy, const char *what) noexcept
{
    libusb_fill_bulk_transfer(transfer, handle_, endpoint, buffer, static_cast<int>(length),
                              &LibusbTransport::onTransferDone, this, 0);
    completed = 0;
    const int rc = api_->submitTransfer(transfer);
    if (rc != 0) {
        if (rc == LIBUSB_ERROR_NO_DEVICE)
            gone_.store(true, std::memory_order_release);
        return unexpected(libusbError(rc, what));
    }
    busy = 1;
    return ok();
}

Result<void> LibusbTransport::submitIn() noexcept
{
    return submit(in_, kEndpointIn, inBuf_.data(), inBuf_.size(), inCompleted_, inBusy_,
                  "Failed to submit the USB IN transfer");
}

Result<std::size_t> LibusbTransport::exchange(const std::uint8_t *out, std::size_t outSize,
                                              std::uint8_t *in, std::size_t inCapacity,
                                              platform::Duration timeout) noexcept
{
    if (!present())
        return unexpected(Errc::NoDevice, "USB device gone");
    if (outBusy_ == 0 && outSize > 0) {
        const std::size_t n = std::min(outSize, outBuf_.size());
        std::memcpy(outBuf_.data(), out, n);
        DT_TRY(submit(out_, kEndpointOut, outBuf_.data(), n, outCompleted_, outBusy_,
                      "Failed to submit the USB OUT transfer"));
    }
    if (inBusy_ == 0)
        DT_TRY(submitIn());

    platform::Clock &clock = platform::SteadyClock::instance();
    const platform::TimePoint deadline = clock.now() + timeout;
    for (;;) {
        while (inCompleted_ == 0 && present()) {
            const auto left = std::chrono::duration_cast<std::chrono::microseconds>(
                deadline - clock.now());
            if (left.count() <= 0)
                return unexpected(Errc::Timeout, "USB device did not answer in time");
            const int rc = handleEvents(static_cast<long>(left.count()), &inCompleted_);
            if (rc != 0 && rc != LIBUSB_ERROR_INTERRUPTED && rc != LIBUSB_ERROR_TIMEOUT)
                return unexpected(libusbError(rc, "USB event handling failed"));
        }
        if (!present())
            return unexpected(Errc::NoDevice, "USB device unplugged");
        if (in_->status != LIBUSB_TRANSFER_COMPLETED)
            return unexpected(Errc::Io, "USB IN transfer failed");
        const std::size_t payload =
            stripFtdiStatus(inBuf_.data(), static_cast<std::size_t>(in_->actual_length));
        if (payload > 0) {
            const std::size_t take = std::min(payload, inCapacity);
            std::memcpy(in, inBuf_.data(), take);
            return take;
        }
        // Only modem status (the FTDI chip sends it every latency period): keep waiting.
        DT_TRY(submitIn());
    }
}

} // namespace depthtouch::drivers
