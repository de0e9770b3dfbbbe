#pragma once
/// \file
/// \brief Plain data types shared by every HAL interface: vectors, pixel formats, image views,
/// stream kinds, presentation times, dma-buf descriptors (DmaBufImage) and FrameRef, the RAII
/// borrow of a backend-owned frame.
///
/// Units: Vec3 holds metres (positions) or newtons (forces) or metres per second (velocities), as
/// the field using it says. Times are platform::Duration / platform::TimePoint (nanoseconds).
/// Thread-safety: value types; FrameRef may be moved to and destroyed on any thread (see
/// FrameOwner). The header is C++17-clean and includes no library header.

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/macros.h"

namespace depthtouch::hal {

/// An absolute deadline on the backend's clock (BackendConfig::clock).
using Deadline = platform::TimePoint;

/// \brief A position on a stream's timeline (nanoseconds from the start of the stream).
///
/// Backends convert their container time base to this once, so callers never see time bases.
using Pts = platform::Duration;

/// A Pts that is not known (a packet without a timestamp).
inline constexpr Pts kNoPts = Pts::min();

/// \brief A 3-vector of doubles: metres (position), newtons (force) or m/s (velocity).
///
/// The frame the coordinates are expressed in is stated by each field that holds one.
struct Vec3 {
    double x = 0.0;
    double y = 0.0;
    double z = 0.0;

    constexpr Vec3 &operator+=(const Vec3 &o) noexcept
    {
        x += o.x;
        y += o.y;
        z += o.z;
        return *this;
    }
    constexpr Vec3 &operator-=(const Vec3 &o) noexcept
    {
        x -= o.x;
        y -= o.y;
        z -= o.z;
        return *this;
    }
    constexpr Vec3 &operator*=(double s) noexcept
    {
        x *= s;
        y *= s;
        z *= s;
        return *this;
    }
};

constexpr Vec3 operator+(Vec3 a, const Vec3 &b) noexcept
{
    return a += b;
}
constexpr Vec3 operator-(Vec3 a, const Vec3 &b) noexcept
{
    return a -= b;
}
constexpr Vec3 operator*(Vec3 a, double s) noexcept
{
    return a *= s;
}
constexpr Vec3 operator*(double s, Vec3 a) noexcept
{
    return a *= s;
}
constexpr bool operator==(const Vec3 &a, const Vec3 &b) noexcept
{
    return a.x == b.x && a.y == b.y && a.z == b.z;
}
constexpr bool operator!=(const Vec3 &a, const Vec3 &b) noexcept
{
    return !(a == b);
}
/// Dot product.
constexpr double dot(const Vec3 &a, const Vec3 &b) noexcept
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
/// Euclidean length.
inline double norm(const Vec3 &v) noexcept
{
    return std::sqrt(dot(v, v));
}
/// True when every component is finite (no NaN, no infinity).
inline bool isFinite(const Vec3 &v) noexcept
{
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

/// A rational number (frame rates, container time bases). den == 0 means unknown.
struct Rational {
    int num = 0;
    int den = 0;

    [[nodiscard]] constexpr double toDouble() const noexcept
    {
        return den != 0 ? static_cast<double>(num) / static_cast<double>(den) : 0.0;
    }
};

/// \brief Pixel formats of decoded frames, camera images and display surfaces.
///
/// Multi-byte samples are in host byte order. "Nearness" depth (Gray8/Gray10/Gray16 in a depth
/// stream) follows docs/architecture.md §3: 0 = farthest, maximum = nearest.
enum class PixelFormat : std::uint8_t {
    Unknown,
    Gray8,   ///< 1 plane, 8 bits per sample.
    Gray10,  ///< 1 plane, 16-bit samples holding 10 significant bits (0..1023), LSB-aligned.
    Gray16,  ///< 1 plane, 16 bits per sample.
    Yuv420p, ///< 3 planes Y, U, V; chroma halved in both directions (rounded up), 8 bits.
    Nv12, ///< 2 planes Y and interleaved UV; chroma halved in both directions (rounded up), 8 bits.
    Rgb24, ///< 1 plane, R G B bytes.
    Rgba8, ///< 1 plane, R G B A bytes.
    Yuyv,  ///< 1 plane, packed 4:2:2 Y0 U Y1 V (width rounded up to even).
    Z16,   ///< 1 plane, 16-bit metric depth in millimetres; 0 = no measurement.
    Mjpeg, ///< Compressed JPEG bytes in plane 0 (ImageView::bytesUsed gives the size).
};

/// \return the format's name, e.g. "yuv420p" (static string; "unknown" for an unknown value).
const char *pixelFormatName(PixelFormat format) noexcept;
/// \return the number of planes of \a format (0 for Unknown).
int planeCount(PixelFormat format) noexcept;
/// \return the significant bits per sample (8, 10 or 16; 0 for Unknown and Mjpeg).
int bitsPerSample(PixelFormat format) noexcept;

/// Bytes in one row and number of rows of one plane of a tightly packed image.
struct PlaneLayout {
    int rowBytes = 0;
    int rows = 0;
};

/// \return the tightly packed layout of plane \a plane of a \a width × \a height image of \a
/// format; {0, 0} for an invalid plane, an unknown or compressed format, or a non-positive size.
PlaneLayout planeLayout(PixelFormat format, int width, int height, int plane) noexcept;

/// \return the bytes of a tightly packed \a width × \a height image of \a format (sum of its
/// planes).
std::size_t imageBytes(PixelFormat format, int width, int height) noexcept;

/// One plane of an image: first byte and distance between rows in bytes.
struct ImagePlane {
    std::uint8_t *data = nullptr;
    int strideBytes = 0;
};

/// \brief A non-owning view of an image in memory. Who owns the memory is said by whoever hands the
/// view out (for a FrameRef: the backend, until the FrameRef is destroyed).
struct ImageView {
    int width = 0;  ///< Pixels.
    int height = 0; ///< Pixels.
    PixelFormat format = PixelFormat::Unknown;
    std::array<ImagePlane, 3> planes{}; ///< planeCount(format) entries are used.
    std::size_t bytesUsed = 0;          ///< Compressed formats only: payload bytes in plane 0.

    /// \return the first byte of row \a y of plane \a plane (no bounds check).
    [[nodiscard]] std::uint8_t *row(int plane, int y) const noexcept
    {
        const auto &p = planes[static_cast<std::size_t>(plane)];
        return p.data + static_cast<std::ptrdiff_t>(y) * p.strideBytes;
    }
    [[nodiscard]] bool empty() const noexcept { return planes[0].data == nullptr; }
};

/// What a video stream or frame carries.
enum class StreamKind : std::uint8_t {
    Color, ///< Texture video (YUV or RGB).
    Depth, ///< Depth video: nearness (Gray*) or metric millimetres (Z16).
};

/// \return "color" or "depth" (static string).
const char *streamKindName(StreamKind kind) noexcept;

/// \return the DRM fourcc code of the four characters \a a \a b \a c \a d (drm_fourcc.h
/// `fourcc_code`: little-endian, \a a in the lowest byte).
constexpr std::uint32_t drmFourcc(char a, char b, char c, char d) noexcept
{
    return static_cast<std::uint32_t>(static_cast<unsigned char>(a)) |
           static_cast<std::uint32_t>(static_cast<unsigned char>(b)) << 8 |
           static_cast<std::uint32_t>(static_cast<unsigned char>(c)) << 16 |
           static_cast<std::uint32_t>(static_cast<unsigned char>(d)) << 24;
}

/// DRM_FORMAT_NV12: 2 planes, Y then interleaved CbCr (Cb first), chroma halved both ways, 8 bits.
inline constexpr std::uint32_t kDrmFormatNv12 = drmFourcc('N', 'V', '1', '2');
/// DRM_FORMAT_YUV420: 3 planes Y, Cb, Cr, chroma halved both ways, 8 bits.
inline constexpr std::uint32_t kDrmFormatYuv420 = drmFourcc('Y', 'U', '1', '2');
/// DRM_FORMAT_MOD_LINEAR: rows of pixels one after the other (no tiling, no compression).
inline constexpr std::uint64_t kDrmFormatModLinear = 0;
/// DRM_FORMAT_MOD_INVALID: no explicit modifier; the layout is implied by the driver (in practice
/// linear for V4L2 decoders).
inline constexpr std::uint64_t kDrmFormatModInvalid = 0x00ffffffffffffffULL;

/// \brief One plane of a dma-buf image: where its first byte is and how far apart its rows are.
struct DmaBufPlane {
    int fd = -1;              ///< The dma-buf (memory object) holding the plane; borrowed.
    std::uint32_t offset = 0; ///< Bytes from the start of the object to the plane's first row.
    std::uint32_t pitch = 0;  ///< Bytes from one row to the next.
};

/// \brief A frame in device memory shared as Linux dma-bufs (DRM PRIME), as a GPU can import it
/// (EGL_EXT_image_dma_buf_import).
///
/// The layout follows DRM: a fourcc (kDrmFormatNv12, kDrmFormatYuv420) that fixes the number and
/// meaning of the planes, a format modifier for tiling (kDrmFormatModLinear, or
/// kDrmFormatModInvalid when the driver implies it), and up to 4 planes, each in a dma-buf object
/// (several planes may share one fd at different offsets).
///
/// Ownership: the fds belong to the backend that lent the frame. They stay open and the memory
/// unchanged while the FrameRef is held; the borrower never closes them and must not use them
/// after dropping the FrameRef (an importer that keeps a GPU image of a buffer must keep the
/// FrameRef until the GPU is done with it). An empty descriptor (planeCount 0, the default) means
/// the frame has no dma-buf. Thread-safety: plain value.
struct DmaBufImage {
    static constexpr int kMaxPlanes = 4;

    std::uint32_t fourcc = 0;                      ///< DRM fourcc; 0 when there is no dma-buf.
    std::uint64_t modifier = kDrmFormatModInvalid; ///< DRM format modifier, same for every plane.
    int width = 0;                                 ///< Pixels.
    int height = 0;                                ///< Pixels.
    int planeCount = 0;                            ///< Planes used in \a planes (0..kMaxPlanes).
    std::array<DmaBufPlane, kMaxPlanes> planes{};

    /// True when the frame carries no dma-buf.
    [[nodiscard]] constexpr bool empty() const noexcept { return planeCount == 0; }
};

/// \return the planes of DRM format \a fourcc: 2 for kDrmFormatNv12, 3 for kDrmFormatYuv420, 0 for
/// a format the HAL does not describe.
constexpr int drmPlaneCount(std::uint32_t fourcc) noexcept
{
    return fourcc == kDrmFormatNv12 ? 2 : fourcc == kDrmFormatYuv420 ? 3 : 0;
}

/// \brief A decoded or captured frame as the backend describes it.
///
/// Lives in the backend's pool; reached only through a FrameRef, which keeps it valid.
struct Frame {
    ImageView image; ///< Pixels. Read-only for the borrower.
    StreamKind kind = StreamKind::Color;
    Pts pts = kNoPts; ///< Stream timeline (decoders) or time since start() (cameras).
    platform::TimePoint
        time{}; ///< When the backend produced the frame, on its BackendConfig clock.
    std::uint64_t sequence =
        0;                ///< Counts frames the source produced; a gap means frames were dropped.
    bool corrupt = false; ///< The data was damaged and the backend concealed the error.
    /// The frame as dma-bufs (zero-copy decoders), besides or instead of CPU planes: when it is
    /// not empty, \a image may be empty (width, height and format still set). Valid, like \a image,
    /// while the FrameRef is held. Empty for every CPU-only backend.
    DmaBufImage dmabuf{};
};

/// \brief The pool side of FrameRef: a backend that lends frames implements it.
///
/// releaseFrame() is called exactly once per lent frame, when its FrameRef is destroyed or reset.
/// Every implementation must make it thread-safe, noexcept, allocation-free and lock-free (a
/// FrameRef may be dropped on the render or the haptic thread).
class FrameOwner {
public:
    virtual ~FrameOwner() = default;

    /// \brief Returns the frame in pool slot \a slot to the pool.
    /// \param[in] slot The slot number the backend gave to the FrameRef.
    virtual void releaseFrame(std::uint32_t slot) noexcept = 0;

protected:
    FrameOwner() = default;
    DT_DISABLE_COPY_AND_MOVE(FrameOwner)
};

/// \brief RAII borrow of a backend-owned frame. Move-only.
///
/// While a FrameRef holds a frame, the backend neither writes nor reuses it. Destroying or
/// reset()ting the FrameRef returns the frame to its pool (FrameOwner::releaseFrame()). The backend
/// object must outlive every FrameRef it handed out. A FrameRef may be moved to another thread and
/// destroyed there.
class FrameRef {
public:
    FrameRef() noexcept = default;
    /// Made by backends only: \a frame lives in slot \a slot of \a owner's pool.
    FrameRef(FrameOwner *owner, std::uint32_t slot, const Frame *frame) noexcept
        : owner_(owner), frame_(frame), slot_(slot)
    {
    }
    FrameRef(FrameRef &&other) noexcept
        : owner_(other.owner_), frame_(other.frame_), slot_(other.slot_)
    {
        other.owner_ = nullptr;
        other.frame_ = nullptr;
    }
    FrameRef &operator=(FrameRef &&other) noexcept
    {
        if (this != &other) {
            reset();
            owner_ = other.owner_;
            frame_ = other.frame_;
            slot_ = other.slot_;
            other.owner_ = nullptr;
            other.frame_ = nullptr;
        }
        return *this;
    }
    FrameRef(const FrameRef &) = delete;
    FrameRef &operator=(const FrameRef &) = delete;
    ~FrameRef() { reset(); }

    /// Returns the frame to its pool now; the FrameRef becomes empty.
    void reset() noexcept
    {
        if (owner_ != nullptr)
            owner_->releaseFrame(slot_);
        owner_ = nullptr;
        frame_ = nullptr;
    }

    /// True when the FrameRef holds a frame.
    explicit operator bool() const noexcept { return frame_ != nullptr; }
    /// \pre the FrameRef holds a frame.
    const Frame &operator*() const noexcept { return *frame_; }
    /// \pre the FrameRef holds a frame.
    const Frame *operator->() const noexcept { return frame_; }
    /// \return the frame, or nullptr when empty.
    [[nodiscard]] const Frame *get() const noexcept { return frame_; }

private:
    FrameOwner *owner_ = nullptr;
    const Frame *frame_ = nullptr;
    std::uint32_t slot_ = 0;
};

} // namespace depthtouch::hal
