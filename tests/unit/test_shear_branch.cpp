// gf-shear --branch-velocities: the start state of a branch from a stored frame under each
// rule (scale, keep, reset), on a two-grain trajectory with known velocities. Every number
// is dyadic, so every answer is exact.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "core/error.hpp"
#include "io/trajectory.hpp"
#include "shear/shear.hpp"

using namespace granflow;
namespace fs = std::filesystem;

namespace {

// Box 8 × 8, γ̇₀ = 1/2. Grain 0 at y = 2, grain 1 at y = 3 (touching, R = 1/2): mean flow
// γ̇₀(y − 4) = −1 and −1/2, spin −γ̇₀/2 = −1/4. Fluctuations ṽ₀ = (1/4, 1/8),
// ṽ₁ = (−1/8, −1/4), ω + γ̇₀/2 = 1/2 and −1/8. One contact (0, 1) of age 7.
constexpr double kSourceRate = 0.5;

class ShearBranch : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("granflow_shear_branch_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A one-frame trajectory of the two grains: moving as above, or at rest (a packing).
  std::string write(bool moving) const {
    const std::string path = (dir_ / (moving ? "run.h5" : "packing.h5")).string();
    io::Frame f;
    f.box = Box{8, 8, true, 0};
    f.position = {Vec2(4, 2), Vec2(4, 3)};
    f.orientation = {0, 0};
    if (moving) {
      f.velocity = {Vec2(-0.75, 0.125), Vec2(-0.625, -0.25)};
      f.angular_velocity = {0.25, -0.375};
      f.has_contacts = true;
      f.contacts.pair = {{0, 1}};
      f.contacts.normal_force = {2};
      f.contacts.tangential_force = {0.5};
      f.contacts.branch = {Vec2(0, -1)};
      f.contacts.binary_force = {1};
      f.contacts.pre_normal_velocity = {{0.25, -0.125}};
      f.contacts.age = {7};
    } else {
      f.velocity = {Vec2::Zero(), Vec2::Zero()};
      f.angular_velocity = {0, 0};
    }
    io::TrajectoryWriter writer(path);
    writer.write_grains({{0.5, 0.5}, {disk_mass(0.5), disk_mass(0.5)}, {0, 0}}, f.box);
    writer.set_lees_edwards_rate(moving ? kSourceRate : 0.0);
    writer.append_frame(f);
    writer.close();
    return path;
  }

  static ShearStart start(const std::string& path, double rate, std::optional<BranchVelocities> mode) {
    io::TrajectoryReader input(path);
    return shear_start(input, -1, rate, 0, 1, mode);
  }

  fs::path dir_;
};

struct Expected {
  Vec2 v0, v1;
  double w0, w1;
};

void expect_state(const ShearStart& s, const Expected& e) {
  EXPECT_FALSE(s.fresh);
  ASSERT_EQ(s.grains.size(), 2u);
  EXPECT_EQ(s.grains.velocity[0], e.v0) << s.grains.velocity[0].transpose();
  EXPECT_EQ(s.grains.velocity[1], e.v1) << s.grains.velocity[1].transpose();
  EXPECT_EQ(s.grains.angular_velocity[0], e.w0);
  EXPECT_EQ(s.grains.angular_velocity[1], e.w1);
  // Positions never change.
  EXPECT_EQ(s.grains.position[0], Vec2(4, 2));
  EXPECT_EQ(s.grains.position[1], Vec2(4, 3));
}

// The contacts in every mode: pairs and ages kept, forces × a², pre-step normal velocities × a.
void expect_contacts(const ShearStart& s, double a) {
  ASSERT_EQ(s.contacts.size(), 1u);
  EXPECT_EQ(s.contacts.age[0], 7);
  EXPECT_EQ(s.contacts.normal_force[0], 2 * a * a);
  EXPECT_EQ(s.contacts.tangential_force[0], 0.5 * a * a);
  EXPECT_EQ(s.contacts.binary_force[0], 1 * a * a);
  EXPECT_EQ(s.contacts.pre_normal_velocity[0][0], 0.25 * a);
  EXPECT_EQ(s.contacts.pre_normal_velocity[0][1], -0.125 * a);
}

}  // namespace

// ---- reversal, γ̇ = −γ̇₀ = −1/2: new mean flow +1 and +1/2, new spin +1/4 ----

TEST_F(ShearBranch, ReversalScaleReversesEveryVelocity) {
  const std::string run = write(true);
  const Expected e{Vec2(0.75, -0.125), Vec2(0.625, 0.25), -0.25, 0.375};
  expect_state(start(run, -0.5, BranchVelocities::scale), e);
  expect_state(start(run, -0.5, std::nullopt), e);  // the default
  expect_contacts(start(run, -0.5, BranchVelocities::scale), -1);
}

TEST_F(ShearBranch, ReversalKeepReversesTheMeanFlowOnly) {
  const std::string run = write(true);
  // ṽ + (1, 0) = (5/4, 1/8), ṽ + (1/2, 0) = (3/8, −1/4); 1/4 + 1/2, 1/4 − 1/8.
  const ShearStart s = start(run, -0.5, BranchVelocities::keep);
  expect_state(s, {Vec2(1.25, 0.125), Vec2(0.375, -0.25), 0.75, 0.125});
  expect_contacts(s, -1);
}

TEST_F(ShearBranch, ReversalResetIsTheAffineFlow) {
  const std::string run = write(true);
  const ShearStart s = start(run, -0.5, BranchVelocities::reset);
  expect_state(s, {Vec2(1, 0), Vec2(0.5, 0), 0.25, 0.25});
  expect_contacts(s, -1);
}

// ---- another magnitude, γ̇ = 3γ̇₀ = 3/2: mean flow −3 and −3/2, spin −3/4 ----

TEST_F(ShearBranch, TripleRateScale) {
  const std::string run = write(true);
  const ShearStart s = start(run, 1.5, BranchVelocities::scale);
  expect_state(s, {Vec2(-2.25, 0.375), Vec2(-1.875, -0.75), 0.75, -1.125});
  expect_contacts(s, 3);
}

TEST_F(ShearBranch, TripleRateKeep) {
  const std::string run = write(true);
  const ShearStart s = start(run, 1.5, BranchVelocities::keep);
  expect_state(s, {Vec2(-2.75, 0.125), Vec2(-1.625, -0.25), -0.25, -0.875});
  expect_contacts(s, 3);
}

TEST_F(ShearBranch, TripleRateReset) {
  const std::string run = write(true);
  const ShearStart s = start(run, 1.5, BranchVelocities::reset);
  expect_state(s, {Vec2(-3, 0), Vec2(-1.5, 0), -0.75, -0.75});
  expect_contacts(s, 3);
}

// ---- the same rate: scale and keep leave the frame as it is, reset does not ----

TEST_F(ShearBranch, SameRate) {
  const std::string run = write(true);
  const Expected stored{Vec2(-0.75, 0.125), Vec2(-0.625, -0.25), 0.25, -0.375};
  for (auto mode : {BranchVelocities::scale, BranchVelocities::keep}) {
    const ShearStart s = start(run, kSourceRate, mode);
    expect_state(s, stored);
    expect_contacts(s, 1);
  }
  expect_state(start(run, kSourceRate, BranchVelocities::reset), {Vec2(-1, 0), Vec2(-0.5, 0), -0.25, -0.25});
}

// ---- refusals ----

TEST_F(ShearBranch, ModeWithAPackingIsRefused) {
  const std::string packing = write(false);
  for (auto mode : {BranchVelocities::scale, BranchVelocities::keep, BranchVelocities::reset}) {
    try {
      start(packing, 1, mode);
      ADD_FAILURE() << "a mode was accepted with a packing";
    } catch (const UsageError& e) {
      EXPECT_NE(std::string(e.what()).find("--branch-velocities"), std::string::npos) << e.what();
    }
  }
  // Without a mode: the affine start, γ̇(y − 4) = −2 and −1 at γ̇ = 1.
  const ShearStart s = start(packing, 1, std::nullopt);
  EXPECT_TRUE(s.fresh);
  EXPECT_EQ(s.grains.velocity[0], Vec2(-2, 0));
  EXPECT_EQ(s.grains.velocity[1], Vec2(-1, 0));
  EXPECT_EQ(s.grains.angular_velocity[0], -0.5);
}

TEST_F(ShearBranch, RateChangeFromOrToZeroIsRefusedInEveryMode) {
  const std::string run = write(true);
  for (auto mode : {BranchVelocities::scale, BranchVelocities::keep, BranchVelocities::reset})
    EXPECT_THROW(start(run, 0, mode), UsageError);
}

TEST_F(ShearBranch, ModeNames) {
  EXPECT_EQ(branch_velocities_named("scale"), BranchVelocities::scale);
  EXPECT_EQ(branch_velocities_named("keep"), BranchVelocities::keep);
  EXPECT_EQ(branch_velocities_named("reset"), BranchVelocities::reset);
  for (const char* bad : {"", "Scale", "reverse", "keep "}) {
    try {
      branch_velocities_named(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const UsageError& e) {
      EXPECT_NE(std::string(e.what()).find("--branch-velocities"), std::string::npos) << e.what();
    }
  }
}
