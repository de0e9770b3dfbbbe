#pragma once
// A stand-in for libusb-1.0 behind LibusbApi: one USB bus with scripted devices, so tests can play
// a device on the USB side of LibusbTransport. It keeps libusb's contracts (LIBUSB_ERROR_* codes,
// a submitted transfer completes once, inside handleEvents, through its callback; a cancelled one
// completes with LIBUSB_TRANSFER_CANCELLED) and records what the transport did.
//
// One bus at a time (LibusbStandin::current, set by the constructor): libusb_init() has nothing to
// find it by. Single-threaded, like the transport.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <thread>
#include <vector>

#include <libusb.h>

#include "depthtouch/drivers/usb/libusb_transport.h"

namespace depthtouch::drivers::testing {

class LibusbStandin {
public:
    /// A device on the bus.
    struct Device {
        std::uint16_t vendorId = 0;
        std::uint16_t productId = 0;
        int openResult = 0; ///< What libusb_open() returns for it (0 or LIBUSB_ERROR_*).
    };
    /// One answer of a bulk IN endpoint: a libusb result (sync) or transfer status (async), and the
    /// bytes as the FTDI chip sends them (two modem-status bytes at the start of every 64).
    struct InAnswer {
        int result = 0;
        std::vector<std::uint8_t> bytes;
    };
    struct ControlCall {
        std::uint8_t requestType;
        std::uint8_t request;
        std::uint16_t value;
        std::uint16_t index;
        std::uint16_t length;
    };

    LibusbStandin() { current = this; }
    ~LibusbStandin() { current = nullptr; }
    LibusbStandin(const LibusbStandin &) = delete;
    LibusbStandin &operator=(const LibusbStandin &) = delete;

    /// \name The bus (set before the transport uses it)
    ///@{
    int initResult = 0;
    int listResult = 0; ///< A LIBUSB_ERROR_* makes libusb_get_device_list() fail.
    std::vector<Device> devices;
    int claimResult = 0;
    int controlResult = 0;   ///< Returned by every control transfer (0: done).
    int bulkOutResult = 0;   ///< Returned by a synchronous bulk OUT.
    int bulkOutAccepts = -1; ///< Bytes a synchronous bulk OUT takes; −1: all.
    int submitResult = 0;    ///< Returned by libusb_submit_transfer().
    int handleEventsResult = 0;
    bool outCompletes = true;     ///< An asynchronous OUT completes on the next event handling.
    std::deque<InAnswer> syncIn;  ///< Answers of synchronous bulk IN transfers; empty: timeout.
    std::deque<InAnswer> asyncIn; ///< Answers of asynchronous IN transfers; empty: none yet.
    /// The device: called with the bytes of each completed OUT transfer (synchronous or not);
    /// what it returns (payload, without status bytes) is queued as the next IN answer.
    std::function<std::vector<std::uint8_t>(const std::vector<std::uint8_t> &)> device;
    ///@}

    /// Unplugs the device: every later call fails with LIBUSB_ERROR_NO_DEVICE and posted transfers
    /// complete with LIBUSB_TRANSFER_NO_DEVICE on the next event handling.
    void unplug() { unplugged = true; }

    /// \name What the transport did
    ///@{
    int inits = 0, exits = 0, opens = 0, closes = 0, claims = 0, releases = 0;
    int allocs = 0, frees = 0, inSubmits = 0, outSubmits = 0, cancels = 0, eventCalls = 0;
    std::vector<ControlCall> controls;
    std::vector<std::vector<std::uint8_t>> written; ///< Completed OUT transfers, in order.
    ///@}

    /// Two FTDI modem-status bytes before \a payload, as one USB packet.
    static std::vector<std::uint8_t> withStatus(std::vector<std::uint8_t> payload)
    {
        payload.insert(payload.begin(), {0x31, 0x60});
        return payload;
    }

    static const LibusbApi &api()
    {
        static const LibusbApi table{
            .init = &init,
            .exit = &exit,
            .getDeviceList = &getDeviceList,
            .freeDeviceList = &freeDeviceList,
            .getDeviceDescriptor = &getDeviceDescriptor,
            .open = &open,
            .close = &close,
            .setAutoDetachKernelDriver = [](libusb_device_handle *, int) { return 0; },
            .claimInterface = &claimInterface,
            .releaseInterface = &releaseInterface,
            .controlTransfer = &controlTransfer,
            .bulkTransfer = &bulkTransfer,
            .allocTransfer = &allocTransfer,
            .freeTransfer = &freeTransfer,
            .submitTransfer = &submitTransfer,
            .cancelTransfer = &cancelTransfer,
            .handleEventsTimeoutCompleted = &handleEvents,
        };
        return table;
    }

    static inline LibusbStandin *current = nullptr;

private:
    static libusb_context *contextOf(LibusbStandin *s)
    {
        return reinterpret_cast<libusb_context *>(s);
    }
    static libusb_device_handle *handleOf(LibusbStandin *s)
    {
        return reinterpret_cast<libusb_device_handle *>(s);
    }

    static int init(libusb_context **ctx)
    {
        if (current->initResult != 0)
            return current->initResult;
        ++current->inits;
        *ctx = contextOf(current);
        return 0;
    }
    static void exit(libusb_context *) { ++current->exits; }
    static ssize_t getDeviceList(libusb_context *, libusb_device ***list)
    {
        if (current->listResult != 0)
            return current->listResult;
        auto *l = new libusb_device *[current->devices.size() + 1];
        for (std::size_t i = 0; i < current->devices.size(); ++i)
            l[i] = reinterpret_cast<libusb_device *>(&current->devices[i]);
        l[current->devices.size()] = nullptr;
        *list = l;
        return static_cast<ssize_t>(current->devices.size());
    }
    static void freeDeviceList(libusb_device **list, int) { delete[] list; }
    static int getDeviceDescriptor(libusb_device *dev, libusb_device_descriptor *desc)
    {
        const auto *d = reinterpret_cast<const Device *>(dev);
        *desc = {};
        desc->idVendor = d->vendorId;
        desc->idProduct = d->productId;
        return 0;
    }
    static int open(libusb_device *dev, libusb_device_handle **handle)
    {
        const auto *d = reinterpret_cast<const Device *>(dev);
        if (d->openResult != 0)
            return d->openResult;
        ++current->opens;
        *handle = handleOf(current);
        return 0;
    }
    static void close(libusb_device_handle *) { ++current->closes; }
    static int claimInterface(libusb_device_handle *, int)
    {
        if (current->claimResult == 0)
            ++current->claims;
        return current->claimResult;
    }
    static int releaseInterface(libusb_device_handle *, int)
    {
        ++current->releases;
        return 0;
    }
    static int controlTransfer(libusb_device_handle *, std::uint8_t requestType,
                               std::uint8_t request, std::uint16_t value, std::uint16_t index,
                               unsigned char *, std::uint16_t length, unsigned int)
    {
        if (current->unplugged)
            return LIBUSB_ERROR_NO_DEVICE;
        current->controls.push_back({requestType, request, value, index, length});
        return current->controlResult;
    }
    void deviceReceives(std::vector<std::uint8_t> bytes)
    {
        if (device) {
            auto answer = device(bytes);
            if (!answer.empty())
                asyncIn.push_back({LIBUSB_TRANSFER_COMPLETED, withStatus(std::move(answer))});
        }
        written.push_back(std::move(bytes));
    }
    static int bulkTransfer(libusb_device_handle *, unsigned char endpoint, unsigned char *data,
                            int length, int *transferred, unsigned int timeoutMs)
    {
        LibusbStandin &s = *current;
        *transferred = 0;
        if (s.unplugged)
            return LIBUSB_ERROR_NO_DEVICE;
        if ((endpoint & LIBUSB_ENDPOINT_IN) == 0) {
            if (s.bulkOutResult != 0)
                return s.bulkOutResult;
            *transferred = s.bulkOutAccepts < 0 ? length : std::min(length, s.bulkOutAccepts);
            s.deviceReceives({data, data + *transferred});
            return 0;
        }
        if (s.syncIn.empty()) {
            std::this_thread::sleep_for(std::chrono::milliseconds(std::min(timeoutMs, 2u)));
            return LIBUSB_ERROR_TIMEOUT;
        }
        if (s.syncIn.front().result != 0) {
            const int rc = s.syncIn.front().result;
            s.syncIn.pop_front();
            return rc;
        }
        *transferred = takeIn(s.syncIn, data, length);
        return 0;
    }
    /// Moves up to \a length bytes of the first answer to \a data; what does not fit stays queued
    /// for the next transfer, as on a device. \return the bytes moved.
    static int takeIn(std::deque<InAnswer> &q, unsigned char *data, int length)
    {
        InAnswer &a = q.front();
        const int n = std::min(length, static_cast<int>(a.bytes.size()));
        std::copy_n(a.bytes.begin(), n, data);
        a.bytes.erase(a.bytes.begin(), a.bytes.begin() + n);
        if (a.bytes.empty())
            q.pop_front();
        return n;
    }
    static libusb_transfer *allocTransfer(int iso)
    {
        ++current->allocs;
        return libusb_alloc_transfer(iso);
    }
    static void freeTransfer(libusb_transfer *t)
    {
        ++current->frees;
        libusb_free_transfer(t);
    }
    static int submitTransfer(libusb_transfer *t)
    {
        LibusbStandin &s = *current;
        if (s.unplugged)
            return LIBUSB_ERROR_NO_DEVICE;
        if (s.submitResult != 0)
            return s.submitResult;
        if ((t->endpoint & LIBUSB_ENDPOINT_IN) != 0) {
            ++s.inSubmits;
            s.postedIn = t;
        } else {
            ++s.outSubmits;
            s.postedOut = t;
        }
        return 0;
    }
    static int cancelTransfer(libusb_transfer *t)
    {
        LibusbStandin &s = *current;
        ++s.cancels;
        if (t != s.postedIn && t != s.postedOut)
            return LIBUSB_ERROR_NOT_FOUND;
        s.cancelled.push_back(t);
        return 0;
    }
    static void complete(libusb_transfer *t, libusb_transfer_status status, int length)
    {
        LibusbStandin &s = *current;
        if (t == s.postedIn)
            s.postedIn = nullptr;
        if (t == s.postedOut)
            s.postedOut = nullptr;
        s.cancelled.erase(std::remove(s.cancelled.begin(), s.cancelled.end(), t),
                          s.cancelled.end());
        t->status = status;
        t->actual_length = length;
        t->callback(t);
    }
    static int handleEvents(libusb_context *, timeval *tv, int *)
    {
        LibusbStandin &s = *current;
        ++s.eventCalls;
        if (s.handleEventsResult != 0)
            return s.handleEventsResult;
        bool any = false;
        while (!s.cancelled.empty()) {
            complete(s.cancelled.front(),
                     s.unplugged ? LIBUSB_TRANSFER_NO_DEVICE : LIBUSB_TRANSFER_CANCELLED, 0);
            any = true;
        }
        if (s.unplugged) {
            for (libusb_transfer *t : {s.postedOut, s.postedIn})
                if (t != nullptr) {
                    complete(t, LIBUSB_TRANSFER_NO_DEVICE, 0);
                    any = true;
                }
            return 0;
        }
        if (libusb_transfer *t = s.postedOut; t != nullptr && s.outCompletes) {
            s.deviceReceives({t->buffer, t->buffer + t->length});
            complete(t, LIBUSB_TRANSFER_COMPLETED, t->length);
            any = true;
        }
        if (libusb_transfer *t = s.postedIn; t != nullptr && !s.asyncIn.empty()) {
            const auto status = static_cast<libusb_transfer_status>(s.asyncIn.front().result);
            const int n = takeIn(s.asyncIn, t->buffer, t->length);
            complete(t, status, n);
            any = true;
        }
        if (!any) // nothing happened: libusb waits for the timeout (capped to keep tests quick)
            std::this_thread::sleep_for(
                std::min(std::chrono::microseconds(tv->tv_sec * 1'000'000 + tv->tv_usec),
                         std::chrono::microseconds(2000)));
        return 0;
    }

    bool unplugged = false;
    libusb_transfer *postedIn = nullptr;
    libusb_transfer *postedOut = nullptr;
    std::vector<libusb_transfer *> cancelled;
};

} // namespace depthtouch::drivers::testing
