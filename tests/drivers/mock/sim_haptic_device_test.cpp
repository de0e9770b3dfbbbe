// The simulated hand (backend `sim`): a fingertip mass on a hand spring-damper toward the intended
// position, closed through a virtual wall that this test renders at 1 kHz (zero-order hold).
#include "depthtouch/drivers/mock/sim_haptic_device.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>

#include <gtest/gtest.h>

#include "mock_test_util.h"

namespace depthtouch::drivers {
namespace {

using std::chrono::milliseconds;
using testing::errcOf;

/// A hand on the manual clock; run() closes the loop through a force field at 1 kHz.
class Hand {
public:
    explicit Hand(const char *options)
    {
        auto s = SimHandSettings::parse(hal::OptionList(options));
        EXPECT_TRUE(s) << options;
        settings_ = s ? *s : SimHandSettings{};
        dev_ = std::make_unique<SimHapticDevice>(clock_, settings_);
        EXPECT_TRUE(dev_->open());
    }

    /// Runs \a ms updates of 1 ms; each commands \a field(position). \return the lowest z seen, m.
    double run(int ms, const std::function<hal::Vec3(const hal::Vec3 &p)> &field)
    {
        double lowest = std::numeric_limits<double>::infinity();
        for (int i = 0; i < ms; ++i) {
            clock_.advance(milliseconds(1));
            hal::HapticState s;
            EXPECT_TRUE(dev_->read(s));
            lowest = std::min(lowest, s.position.z);
            const hal::Vec3 f = field(s.position);
            force_ = f.z;
            EXPECT_TRUE(dev_->commandForce(f));
        }
        return lowest;
    }
    /// As above with a vertical force \a field(z).
    double run(int ms, const std::function<double(double z)> &field)
    {
        return run(ms, [&](const hal::Vec3 &p) { return hal::Vec3{0.0, 0.0, field(p.z)}; });
    }

    [[nodiscard]] hal::Vec3 position() const { return dev_->position(); }
    [[nodiscard]] double force() const { return force_; }
    [[nodiscard]] const SimHandSettings &settings() const { return settings_; }
    /// The device, open, for a test that drives it call by call.
    [[nodiscard]] SimHapticDevice &device() { return *dev_; }
    /// The manual clock the device reads.
    [[nodiscard]] platform::ManualClock &clock() { return clock_; }

private:
    platform::ManualClock clock_;
    SimHandSettings settings_;
    std::unique_ptr<SimHapticDevice> dev_;
    double force_ = 0.0;
};

/// A wall at height \a top, stiffness \a k (N/m), pushing up only.
std::function<double(double)> wall(double top, double k)
{
    return [top, k](double z) { return z < top ? k * (top - z) : 0.0; };
}

double freeSpace(double /*z*/)
{
    return 0.0;
}

TEST(SimHandTest, optionsResolveTheHandAndRejectNonsense)
{
    auto d = SimHandSettings::parse(hal::OptionList("intent=stroke"));
    ASSERT_TRUE(d);
    EXPECT_DOUBLE_EQ(d->handStiffness, 300.0);
    EXPECT_DOUBLE_EQ(d->depth, 2.0 / 300.0); // force / hand_stiffness: the old 2 N press
    auto g = SimHandSettings::parse(hal::OptionList("force=1.5,hand_stiffness=250"));
    ASSERT_TRUE(g);
    EXPECT_DOUBLE_EQ(g->depth, 0.006);
    auto e = SimHandSettings::parse(hal::OptionList("depth=0.002,force=5,hand_damping=8,grip=150"));
    ASSERT_TRUE(e);
    EXPECT_DOUBLE_EQ(e->depth, 0.002);
    EXPECT_DOUBLE_EQ(e->handDamping, 8.0);
    EXPECT_DOUBLE_EQ(e->grip, 150.0);
    for (const char *bad : {"depth=-0.001", "hand_stiffness=0", "hand_damping=-1", "follow=0",
                            "reaction=-1", "approach=-0.1", "climb=-1", "reach=0", "depth=abc",
                            "stiffness=300"})
        EXPECT_EQ(errcOf(SimHandSettings::parse(hal::OptionList(bad))), Errc::InvalidArgument)
            << bad;
}

TEST(SimHandTest, freeFingerConvergesToTheIntendedPositionWithoutRinging)
{
    // GIVEN a fixed hand (approach=0) that intends to hold 4 mm below its start height
    Hand hand("intent=press,x=0.01,y=-0.005,z=0.02,depth=0.004,approach=0");
    // WHEN nothing touches it
    const double lowest = hand.run(1000, freeSpace);
    // THEN it settles at the intended position, near-critically damped (no real overshoot)
    const hal::Vec3 p = hand.position();
    EXPECT_NEAR(p.x, 0.01, 1e-6);
    EXPECT_NEAR(p.y, -0.005, 1e-6);
    EXPECT_NEAR(p.z, 0.016, 1e-6);
    EXPECT_GT(lowest, 0.016 - 0.0002);
}

TEST(SimHandTest, fixedHandOnAStiffWallSettlesWhereTheSpringBalancesTheWall)
{
    // GIVEN a fixed hand whose intended height is 2 mm inside a 3000 N/m wall at z = 0
    Hand hand("intent=press,z=0.002,depth=0.004,approach=0");
    const double kWall = 3000.0;
    hand.run(1500, wall(0.0, kWall));
    // THEN the wall's force equals hand spring × (actual − intended)
    const double z = hand.position().z;
    const double intended = -0.002;
    EXPECT_LT(z, 0.0);
    EXPECT_NEAR(hand.force(), 300.0 * (z - intended), 1e-3);
    EXPECT_NEAR(z, 300.0 * intended / (300.0 + kWall), 1e-6);
}

TEST(SimHandTest, feelingHandPressesTheSurfaceItFindsWithSpringTimesDepth)
{
    // GIVEN the default hand (it lowers its surface estimate until it feels the wall, then follows
    // the fingertip), intending 4 mm below the surface it feels
    Hand hand("intent=press,z=0.03,depth=0.004");
    hand.run(2000, wall(-0.01, 3000.0));
    // THEN it rests on the wall, pressing with hand stiffness × depth, whatever the wall's height
    EXPECT_NEAR(hand.force(), 300.0 * 0.004, 0.01);
    EXPECT_NEAR(hand.position().z, -0.01 - 1.2 / 3000.0, 1e-5);
}

TEST(SimHandTest, losingTheSupportSinksTheFingerAtMostTheIntendedDepth)
{
    // GIVEN the hand resting on a wall, 2 N (depth 6.7 mm at 300 N/m), as in the old constant-force
    // model
    Hand hand("intent=press,z=0.01,force=2");
    hand.run(1500, wall(0.0, 3000.0));
    const double before = hand.position().z;
    const double depth = hand.settings().depth;
    ASSERT_NEAR(hand.force(), 2.0, 0.02);
    // WHEN the surface disappears (a hole, a pop-through): no force for the reaction time
    const double lowest = hand.run(150, freeSpace);
    // THEN the finger sinks toward its intended position only: at most the depth, not the
    // 10 mm and more a constant 2 N push would have driven it in 150 ms (0.5·(2/0.1)·0.15² = 0.22
    // m)
    EXPECT_GT(lowest, before - depth - 0.0002);
    EXPECT_LT(lowest, before - 0.5 * depth); // it did sink: the hand was pressing
}

TEST(SimHandTest, fixedHandNeverSinksBelowItsIntendedHeight)
{
    // GIVEN a fixed hand pressing a wall, WHEN the wall goes for good
    Hand hand("intent=press,z=0.003,depth=0.005,approach=0");
    hand.run(1000, wall(0.0, 3000.0));
    const double lowest = hand.run(3000, freeSpace);
    // THEN it stops at its intended height (−2 mm), however long it waits
    EXPECT_GT(lowest, -0.002 - 0.0002);
    EXPECT_NEAR(hand.position().z, -0.002, 1e-6);
}

TEST(SimHandTest, feelingHandFindsASurfaceThatSteppedDown)
{
    // GIVEN the hand resting on a wall at z = 0
    Hand hand("intent=press,z=0.01,depth=0.003");
    hand.run(1000, wall(0.0, 3000.0));
    // WHEN the surface steps down 20 mm (the finger slides off an object onto the backdrop)
    const double lowest = hand.run(1000, wall(-0.02, 3000.0));
    // THEN after its reaction time the hand lowers its estimate, finds the new surface and
    // presses it as before, without falling through it
    EXPECT_NEAR(hand.force(), 0.9, 0.01);
    EXPECT_NEAR(hand.position().z, -0.02 - 0.9 / 3000.0, 1e-5);
    EXPECT_GT(lowest, -0.02 - 0.003);
}

TEST(SimHandTest, strokingHandClimbsOverAStepInItsWay)
{
    // GIVEN a floor at z = 0 and, from x = 0.01 on, a block 15 mm high (its side a wall pushing
    // back along −x: the silhouette of a head in front of a curtain), and a hand stroking from
    // x = −0.01 to 0.03 and back at 5 cm/s, pressing 4 mm in
    const double k = 3000.0;
    const auto scene = [k](const hal::Vec3 &p) {
        if (p.x >= 0.01 && p.z < 0.015) {
            const double side = p.x - 0.01; // into the block from its side
            const double top = 0.015 - p.z; // into the block from its top
            return side < top ? hal::Vec3{-k * side, 0.0, 0.0} : hal::Vec3{0.0, 0.0, k * top};
        }
        return hal::Vec3{0.0, 0.0, p.z < 0.0 ? -k * p.z : 0.0};
    };
    Hand hand("intent=stroke,path=-0.01:0/0.03:0,speed=0.05,z=0.005,depth=0.004");
    // WHEN the stroke reaches the far end of the block (0.8 s at 5 cm/s)
    hand.run(850, scene);
    // THEN the hand has lifted the finger over the side and presses on the block's top
    const hal::Vec3 p = hand.position();
    EXPECT_GT(p.x, 0.02);
    EXPECT_NEAR(p.z, 0.015 - 1.2 / k, 0.002);
    EXPECT_GT(hand.force(), 0.3);
}

TEST(SimHandTest, handThatWentThroughTheSurfaceBacksUpAndTouchesAgain)
{
    // GIVEN the hand resting on a surface at z = 0 that, once, stops pushing while the finger is
    // under it (a renderer that lost its proxy: it pushes again only after the finger came back
    // above the surface)
    Hand hand("intent=press,z=0.01,depth=0.004");
    bool lost = false;
    bool above = true;
    const auto surface = [&](const hal::Vec3 &p) {
        above = above || p.z > 0.0;
        if (lost && p.z < 0.0 && !above)
            return hal::Vec3{};
        return hal::Vec3{0.0, 0.0, p.z < 0.0 ? -3000.0 * p.z : 0.0};
    };
    hand.run(1000, surface);
    ASSERT_NEAR(hand.force(), 1.2, 0.01);
    // WHEN the surface lets the finger through
    lost = true;
    above = false;
    const double lowest = hand.run(2500, surface);
    // THEN it searched at most `reach` (3 cm) below its last touch, went back up and presses the
    // surface again from above
    EXPECT_LT(lowest, -0.02);
    EXPECT_GT(lowest, -0.03 - 0.004 - 0.002);
    EXPECT_NEAR(hand.force(), 1.2, 0.01);
    EXPECT_NEAR(hand.position().z, -1.2 / 3000.0, 1e-5);
}

TEST(SimHandTest, handThatSearchedToTheFloorBeforeTheSceneCameBacksUpAndTouchesIt)
{
    // GIVEN a hand that starts searching before there is anything to touch (a player whose first
    // depth frame comes late on a loaded machine), and a surface at z = 0 that then appears and,
    // like the renderer, pushes a finger found under it only once it came back above it
    Hand hand("intent=press,z=0.01,depth=0.004,delay=0");
    bool appeared = false;
    bool above = false;
    const auto surface = [&](const hal::Vec3 &p) {
        if (!appeared)
            return hal::Vec3{};
        above = above || p.z > 0.0;
        return hal::Vec3{0.0, 0.0, above && p.z < 0.0 ? -3000.0 * p.z : 0.0};
    };
    const double lowest = hand.run(1000, surface);
    // WHEN the surface appears with the finger at the device's end stop (workspace 6 cm)
    ASSERT_NEAR(lowest, -0.06, 1e-9);
    appeared = true;
    hand.run(3000, surface);
    // THEN the hand went back up, found the surface and presses it as intended
    EXPECT_NEAR(hand.force(), 1.2, 0.01);
    EXPECT_NEAR(hand.position().z, -1.2 / 3000.0, 1e-5);
}

TEST(SimHandTest, exploreRefusesAPeriodShorterThanTenMilliseconds)
{
    // GIVEN explore periods of a nanosecond (a FIFO thread spinning for tens of seconds on one
    // call before) and of 10 ms
    // WHEN they are parsed
    // THEN the nonsense is refused with the key's error and the shortest sensible one accepted
    for (const char *bad :
         {"intent=explore,period=1e-9", "intent=explore,period=0.009", "period=0"})
        EXPECT_EQ(errcOf(SimHandSettings::parse(hal::OptionList(bad))), Errc::InvalidArgument)
            << bad;
    EXPECT_TRUE(SimHandSettings::parse(hal::OptionList("intent=explore,period=0.01")));
}

TEST(SimHandTest, oneCallIntegratesAtMostATenthOfASecond)
{
    // GIVEN a free fingertip (no hand) pushed by 0.01 N along x
    Hand hand("intent=idle");
    ASSERT_FALSE(::testing::Test::HasFailure());
    SimHapticDevice &dev = hand.device();
    ASSERT_TRUE(dev.commandForce(hal::Vec3{0.01, 0.0, 0.0}));
    // WHEN the next read comes 10 s later (a stopped process, a jump of the clock)
    hand.clock().advance(std::chrono::seconds(10));
    hal::HapticState s;
    ASSERT_TRUE(dev.read(s));
    // THEN that call integrated 0.1 s of motion at most (v = F·t/m = 0.01 m/s), not 1 s or 10 s
    EXPECT_GT(s.velocity.x, 0.009);
    EXPECT_LT(s.velocity.x, 0.0101);
    // AND the rest of the gap was skipped: the hand's time is the clock's
    EXPECT_EQ(s.time, hand.clock().now());
}

TEST(SimHandTest, exploreHandCatchesUpALongGapInBoundedWork)
{
    // GIVEN an exploring hand with the shortest period, on a manual clock
    Hand hand("intent=explore,period=0.01,seed=5");
    ASSERT_FALSE(::testing::Test::HasFailure());
    SimHapticDevice &dev = hand.device();
    // WHEN a read comes after 10^7 s (10^9 explore points missed)
    hand.clock().advance(std::chrono::seconds(10'000'000));
    hal::HapticState s;
    const auto begin = std::chrono::steady_clock::now();
    ASSERT_TRUE(dev.read(s));
    const auto took = std::chrono::steady_clock::now() - begin;
    // THEN the call returns at once (generous: 0.5 s; drawing every missed point took minutes)
    EXPECT_LT(took, std::chrono::milliseconds(500));
    EXPECT_TRUE(std::isfinite(s.position.x) && std::isfinite(s.position.y));
}

TEST(SimHandTest, runsAreDeterministic)
{
    Hand a("intent=explore,depth=0.005,period=0.2,seed=3");
    Hand b("intent=explore,depth=0.005,period=0.2,seed=3");
    a.run(700, wall(-0.005, 800.0));
    b.run(700, wall(-0.005, 800.0));
    EXPECT_EQ(a.position(), b.position());
    EXPECT_EQ(a.force(), b.force());
}

} // namespace
} // namespace depthtouch::drivers
