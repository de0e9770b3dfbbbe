#include "depthtouch/drivers/mock/sim_haptic_device.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <string>
#include <string_view>

#include "depthtouch/drivers/common/backend_options.h"
#include "depthtouch/platform/log.h"
#include "simulated_caps.h"

DT_LOG_CATEGORY(Sim)

namespace depthtouch::drivers {

namespace {

constexpr const char *kOptionKeys[] = {
    "intent",   "force",     "depth",      "hand_stiffness", "hand_damping", "follow",
    "reaction", "approach",  "climb",      "reach",          "x",            "y",
    "z",        "delay",     "path",       "speed",          "period",       "seed",
    "mass",     "damping",   "grip",       "max_force",      "workspace",    "servo_rate",
    "buttons"};

/// The hand feels the device push above this force, N.
constexpr double kFeelForce = 0.05;
/// Fastest the hand moves its surface estimate while touching, m/s.
constexpr double kMaxEstimateSpeed = 0.2;

/// Integration step of the hand, ns.
constexpr std::int64_t kStepNs = 100'000;
/// Longest stretch integrated by one call (0.1 s of hand motion); the rest of a longer gap (an
/// overrun, a stopped process, a jump of a manual clock) is skipped. It bounds the time of one
/// device call on the haptic thread whatever the options (docs/devices.md "The simulated hand").
constexpr std::int64_t kMaxStepsPerCall = 1'000;
/// Shortest explore period, s: at most one new random point per integration step, and no hand
/// picks more than 100 points a second.
constexpr double kMinExplorePeriod = 0.01;
/// Explore points drawn by one intentAt() at most; further behind (after a skipped gap) the hand
/// drops the points it missed and draws only the last ones.
constexpr std::int64_t kMaxExploreCatchUp = 4;

Error badOption(const char *key, const char *why)
{
    DT_LOG(Sim, Error, "Simulated hand option '%s': %s", key, why);
    return Error(Errc::InvalidArgument, "Invalid simulated hand option");
}

/// Parses "x:y/x:y/..." into \a out. \return the number of points, or -1 when malformed.
int parsePath(std::string_view text, double (*out)[2], int capacity)
{
    int count = 0;
    std::string item;
    std::size_t start = 0;
    while (start <= text.size()) {
        std::size_t end = text.find('/', start);
        if (end == std::string_view::npos)
            end = text.size();
        item.assign(text.substr(start, end - start));
        const std::size_t colon = item.find(':');
        if (colon == std::string::npos || count >= capacity)
            return -1;
        char *stop = nullptr;
        const double x = std::strtod(item.c_str(), &stop);
        if (stop != item.c_str() + colon)
            return -1;
        const char *ys = item.c_str() + colon + 1;
        const double y = std::strtod(ys, &stop);
        if (stop == ys || *stop != '\0' || !std::isfinite(x) || !std::isfinite(y))
            return -1;
        out[count][0] = x;
        out[count][1] = y;
        ++count;
        start = end + 1;
    }
    return count;
}

double clampTo(double v, double lo, double hi) noexcept
{
    return std::min(std::max(v, lo), hi);
}

/// xorshift64*: a small deterministic generator. \return a number in [0, 1).
double nextUniform(std::uint64_t &state) noexcept
{
    state ^= state >> 12;
    state ^= state << 25;
    state ^= state >> 27;
    const std::uint64_t r = state * 2685821657736338717ull;
    return static_cast<double>(r >> 11) * (1.0 / 9007199254740992.0);
}

} // namespace

Result<SimHandSettings> SimHandSettings::parse(hal::OptionList options)
{
    DT_TRY(rejectUnknownOptions(options, kOptionKeys, std::size(kOptionKeys), kLogCategorySim,
                                "Unknown simulated hand option"));
    SimHandSettings s;
    if (const auto intent = options.find("intent")) {
        if (*intent == "press")
            s.intent = Intent::Press;
        else if (*intent == "stroke")
            s.intent = Intent::Stroke;
        else if (*intent == "explore")
            s.intent = Intent::Explore;
        else if (*intent == "idle")
            s.intent = Intent::Idle;
        else
            return unexpected(badOption("intent", "must be press, stroke, explore or idle"));
    }
    struct Number {
        const char *key;
        double *value;
        double min;
        bool minExclusive;
    };
    // Options whose default is derived from others: only read when given.
    const bool depthGiven = options.find("depth").has_value();
    const bool handDampingGiven = options.find("hand_damping").has_value();
    const bool gripGiven = options.find("grip").has_value();
    const Number numbers[] = {
        {"force", &s.force, 0.0, false},
        {"depth", &s.depth, 0.0, false},
        {"hand_stiffness", &s.handStiffness, 0.0, true},
        {"hand_damping", &s.handDamping, 0.0, false},
        {"follow", &s.follow, 0.0, true},
        {"reaction", &s.reaction, 0.0, false},
        {"approach", &s.approach, 0.0, false},
        {"climb", &s.climb, 0.0, false},
        {"reach", &s.reach, 0.0, true},
        {"x", &s.x, -HUGE_VAL, false},
        {"y", &s.y, -HUGE_VAL, false},
        {"z", &s.z, -HUGE_VAL, false},
        {"delay", &s.delay, 0.0, false},
        {"speed", &s.speed, 0.0, true},
        {"period", &s.period, 0.0, true},
        {"mass", &s.mass, 0.0, true},
        {"damping", &s.damping, 0.0, false},
        {"grip", &s.grip, 0.0, false},
        {"max_force", &s.maxForce, 0.0, true},
        {"workspace", &s.workspaceHalfExtent, 0.0, true},
        {"servo_rate", &s.servoRateHz, 0.0, true},
    };
    for (const Number &n : numbers) {
        if ((n.value == &s.depth && !depthGiven) ||
            (n.value == &s.handDamping && !handDampingGiven) || (n.value == &s.grip && !gripGiven))
            continue;
        auto v = options.getDouble(n.key, *n.value);
        if (!v)
            return unexpected(badOption(n.key, "not a number"));
        if (n.minExclusive ? !(*v > n.min) : !(*v >= n.min))
            return unexpected(badOption(n.key, n.minExclusive ? "must be > 0" : "must be >= 0"));
        *n.value = *v;
    }
    if (s.period < kMinExplorePeriod) {
        (void)badOption("period", "must be at least 0.01 s");
        return unexpected(Errc::InvalidArgument,
                          "Simulated hand option period must be at least 0.01 s");
    }
    auto seed = options.getInt("seed", 1);
    if (!seed)
        return unexpected(badOption("seed", "not an integer"));
    s.seed = static_cast<std::uint64_t>(static_cast<std::int64_t>(*seed));
    auto buttons = options.getInt("buttons", s.buttonCount);
    if (!buttons || *buttons < 0 || *buttons > 32)
        return unexpected(badOption("buttons", "must be an integer in 0..32"));
    s.buttonCount = *buttons;
    if (const auto path = options.find("path")) {
        const int n = parsePath(*path, s.path, kMaxPathPoints);
        if (n < 2)
            return unexpected(
                badOption("path", "must be 2 to 16 points 'x:y' separated by '/', in metres"));
        s.pathPoints = n;
    }
    if (!depthGiven)
        s.depth = s.force / s.handStiffness;
    return s;
}

Result<std::unique_ptr<hal::HapticDevice>> SimHapticDevice::create(const hal::BackendConfig &cfg)
{
    return createFromSettings<hal::HapticDevice, SimHapticDevice, SimHandSettings>(cfg);
}

SimHapticDevice::SimHapticDevice(platform::Clock &clock, const SimHandSettings &settings)
    : clock_(clock), settings_(settings)
{
    caps_ =
        simulatedCapabilities("Simulated hand (fingertip mass on a hand spring-damper)", settings);
    const double m = settings.mass;
    kz_ = settings.handStiffness;
    cz_ = settings.handDamping >= 0.0 ? settings.handDamping : 2.0 * std::sqrt(kz_ * m);
    kxy_ = settings.grip >= 0.0 ? settings.grip : kz_;
    // The same damping ratio along x and y as along z.
    cxy_ = cz_ * std::sqrt(kxy_ / kz_);
    for (int i = 1; i < settings.pathPoints; ++i)
        pathLength_ += std::hypot(settings.path[i][0] - settings.path[i - 1][0],
                                  settings.path[i][1] - settings.path[i - 1][1]);
    resetHand();
}

void SimHapticDevice::resetHand() noexcept
{
    const hal::Vec3 &lo = caps_.workspaceMin;
    const hal::Vec3 &hi = caps_.workspaceMax;
    double gx = settings_.x;
    double gy = settings_.y;
    if (settings_.intent == SimHandSettings::Intent::Stroke) {
        gx = settings_.path[0][0];
        gy = settings_.path[0][1];
    }
    pos_ = {clampTo(gx, lo.x, hi.x), clampTo(gy, lo.y, hi.y), clampTo(settings_.z, lo.z, hi.z)};
    vel_ = {};
    force_ = {};
    rng_ = settings_.seed != 0 ? settings_.seed : 0x9E3779B97F4A7C15ull;
    exploreSegment_ = -1;
    exploreTo_[0] = pos_.x;
    exploreTo_[1] = pos_.y;
    exploreFrom_[0] = pos_.x;
    exploreFrom_[1] = pos_.y;
    exploreDepth_ = settings_.depth;
    surfaceEstimate_ = pos_.z;
    lastFeltZ_ = -HUGE_VAL; // no touch yet: search down to the workspace floor
    retreating_ = false;
    unfeltSeconds_ = settings_.reaction; // nothing felt yet: search at once
    lastTarget_ = pos_;
    haveTarget_ = false;
    publishPosition();
}

Result<SimHapticDevice::State> SimHapticDevice::openDevice()
{
    if (!devicePresent())
        return unexpected(Errc::NoDevice, "Simulated hand unplugged");
    resetHand();
    openedAt_ = clock_.now();
    simTime_ = openedAt_;
    setOutput({});
    return State::Open;
}

void SimHapticDevice::zeroForceDevice() noexcept
{
    force_ = {};
    SimulatedHapticDeviceBase::zeroForceDevice();
}

void SimHapticDevice::intentAt(double t, double &gx, double &gy, double &depth) noexcept
{
    gx = settings_.x;
    gy = settings_.y;
    depth = settings_.depth;
    switch (settings_.intent) {
    case SimHandSettings::Intent::Press:
    case SimHandSettings::Intent::Idle:
        break;
    case SimHandSettings::Intent::Stroke: {
        // Arc length along the polyline, back and forth.
        double s =
            pathLength_ > 0.0
                ? std::fmod(settings_.speed * std::max(t - settings_.delay, 0.0), 2.0 * pathLength_)
                : 0.0;
        if (s > pathLength_)
            s = 2.0 * pathLength_ - s;
        gx = settings_.path[0][0];
        gy = settings_.path[0][1];
        for (int i = 1; i < settings_.pathPoints; ++i) {
            const double ax = settings_.path[i - 1][0];
            const double ay = settings_.path[i - 1][1];
            const double bx = settings_.path[i][0];
            const double by = settings_.path[i][1];
            const double length = std::hypot(bx - ax, by - ay);
            if (s <= length || i == settings_.pathPoints - 1) {
                const double f = length > 0.0 ? std::min(s / length, 1.0) : 0.0;
                gx = ax + (bx - ax) * f;
                gy = ay + (by - ay) * f;
                break;
            }
            s -= length;
        }
        break;
    }
    case SimHandSettings::Intent::Explore: {
        const auto segment = static_cast<std::int64_t>(std::floor(t / settings_.period));
        // Generate the targets up to this segment in order (deterministic for a seed).
        const double reach = 0.8 * settings_.workspaceHalfExtent;
        if (segment - exploreSegment_ > kMaxExploreCatchUp)
            exploreSegment_ = segment - kMaxExploreCatchUp;
        while (exploreSegment_ < segment) {
            exploreFrom_[0] = exploreTo_[0];
            exploreFrom_[1] = exploreTo_[1];
            exploreTo_[0] = (2.0 * nextUniform(rng_) - 1.0) * reach;
            exploreTo_[1] = (2.0 * nextUniform(rng_) - 1.0) * reach;
            exploreDepth_ = settings_.depth * (0.2 + 0.8 * nextUniform(rng_));
            ++exploreSegment_;
        }
        const double f = std::clamp(t / settings_.period - static_cast<double>(segment), 0.0, 1.0);
        gx = exploreFrom_[0] + (exploreTo_[0] - exploreFrom_[0]) * f;
        gy = exploreFrom_[1] + (exploreTo_[1] - exploreFrom_[1]) * f;
        depth = exploreDepth_;
        break;
    }
    }
}

void SimHapticDevice::updateSurfaceEstimate(double t, double h, double depth, double ux,
                                            double uy) noexcept
{
    if (t < settings_.delay || settings_.approach <= 0.0)
        return; // hovering, or a fixed hand: the estimate stays at the start height
    const double felt = hal::norm(force_);
    if (felt > kFeelForce) {
        // Touching: regulate the press. Pushed harder than intended (the surface rose) the hand
        // rises, pushed less it goes down: on a still surface the estimate follows the fingertip
        // with time constant `follow` and the press settles at hand stiffness × depth. A force
        // against the stroke (the side of an object in the way) lifts the finger over it.
        unfeltSeconds_ = 0.0;
        retreating_ = false;
        lastFeltZ_ = pos_.z;
        const double against = std::max(0.0, -(force_.x * ux + force_.y * uy));
        const double rate =
            (felt - kz_ * depth) / (kz_ * settings_.follow) + settings_.climb * against;
        surfaceEstimate_ += std::clamp(rate, -kMaxEstimateSpeed, kMaxEstimateSpeed) * h;
        return;
    }
    unfeltSeconds_ += h;
    if (retreating_) {
        // Lost (nothing within reach below the last touch): back up to the start height.
        surfaceEstimate_ += 2.0 * settings_.approach * h;
        if (surfaceEstimate_ >= settings_.z) {
            surfaceEstimate_ = settings_.z;
            retreating_ = false;
        }
        return;
    }
    if (unfeltSeconds_ >= settings_.reaction) {
        surfaceEstimate_ =
            std::max(surfaceEstimate_ - settings_.approach * h, caps_.workspaceMin.z);
        // Went through: `reach` below the last touch, or down at the device's end stop (before
        // any touch, or with the last touch less than `reach` above the floor: a hand that
        // reached the floor with nothing felt does not stay there).
        const bool atFloor = surfaceEstimate_ <= caps_.workspaceMin.z;
        if ((atFloor || surfaceEstimate_ < lastFeltZ_ - settings_.reach) &&
            surfaceEstimate_ < settings_.z)
            retreating_ = true;
    }
}

void SimHapticDevice::step(double h) noexcept
{
    const double t = platform::toSeconds(simTime_ - openedAt_);
    hal::Vec3 f = force_ - vel_ * settings_.damping;
    if (settings_.intent != SimHandSettings::Intent::Idle) {
        double gx = 0.0;
        double gy = 0.0;
        double depth = 0.0;
        intentAt(t, gx, gy, depth);
        // The intended lateral velocity (continuous along a path; zero on the first step).
        double vx = 0.0;
        double vy = 0.0;
        if (haveTarget_) {
            vx = (gx - lastTarget_.x) / h;
            vy = (gy - lastTarget_.y) / h;
        }
        const double lateralSpeed = std::hypot(vx, vy);
        const double ux = lateralSpeed > 1e-3 ? vx / lateralSpeed : 0.0;
        const double uy = lateralSpeed > 1e-3 ? vy / lateralSpeed : 0.0;
        const double estimateBefore = surfaceEstimate_;
        updateSurfaceEstimate(t, h, depth, ux, uy);
        const double gz = t < settings_.delay ? settings_.z : surfaceEstimate_ - depth;
        // The damper acts on the velocity relative to the intended one: the lateral point's and
        // the surface estimate's; steps of the depth (hover → press, a new explore depth) move
        // only the spring's rest point, they are not a velocity.
        const hal::Vec3 targetVel{vx, vy, (surfaceEstimate_ - estimateBefore) / h};
        lastTarget_ = {gx, gy, gz};
        haveTarget_ = true;
        f.x += kxy_ * (gx - pos_.x) + cxy_ * (targetVel.x - vel_.x);
        f.y += kxy_ * (gy - pos_.y) + cxy_ * (targetVel.y - vel_.y);
        f.z += kz_ * (gz - pos_.z) + cz_ * (targetVel.z - vel_.z);
    }
    vel_ += f * (h / settings_.mass);
    pos_ += vel_ * h;
    // Hard stops at the workspace walls.
    const hal::Vec3 &lo = caps_.workspaceMin;
    const hal::Vec3 &hi = caps_.workspaceMax;
    double *p[3] = {&pos_.x, &pos_.y, &pos_.z};
    double *v[3] = {&vel_.x, &vel_.y, &vel_.z};
    const double los[3] = {lo.x, lo.y, lo.z};
    const double his[3] = {hi.x, hi.y, hi.z};
    for (int i = 0; i < 3; ++i) {
        if (*p[i] < los[i]) {
            *p[i] = los[i];
            *v[i] = std::max(*v[i], 0.0);
        } else if (*p[i] > his[i]) {
            *p[i] = his[i];
            *v[i] = std::min(*v[i], 0.0);
        }
    }
}

void SimHapticDevice::integrateToNow() noexcept
{
    const platform::TimePoint now = clock_.now();
    if (now <= simTime_)
        return;
    std::int64_t steps = (now - simTime_).count() / kStepNs;
    if (steps > kMaxStepsPerCall) {
        simTime_ += platform::Duration((steps - kMaxStepsPerCall) * kStepNs);
        steps = kMaxStepsPerCall;
    }
    const double h = static_cast<double>(kStepNs) * 1e-9;
    for (std::int64_t i = 0; i < steps; ++i) {
        step(h);
        simTime_ += platform::Duration(kStepNs);
    }
    if (steps > 0)
        publishPosition();
}

Result<void> SimHapticDevice::readDevice(hal::HapticState &out) noexcept
{
    DT_TRY(checkStall());
    integrateToNow();
    out = hal::HapticState{};
    out.position = pos_;
    out.velocity = vel_;
    out.velocityValid = true;
    out.buttons = 0;
    out.time = simTime_;
    return ok();
}

Result<void> SimHapticDevice::commandForceDevice(const hal::ForceCommand &command) noexcept
{
    DT_TRY(checkStall());
    // The previous force acted until now (zero-order hold).
    integrateToNow();
    force_ = command.force;
    setOutput(command.force);
    return ok();
}

void SimHapticDevice::publishPosition() noexcept
{
    position_.store(pos_);
}

hal::Vec3 SimHapticDevice::position() const noexcept
{
    return position_.load();
}

} // namespace depthtouch::drivers
