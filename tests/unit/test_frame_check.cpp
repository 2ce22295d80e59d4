// No writer puts a non-finite number into a trajectory or a packing: the refusal is a
// RuntimeFailure naming the file and the dataset, and a packing is not even created.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <limits>
#include <string>

#include "core/error.hpp"
#include "io/trajectory.hpp"
#include "packing/packing_io.hpp"

using namespace granflow;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct FrameCheckTest : ::testing::Test {
  std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("granflow_frame_check_" + std::to_string(::getpid()));
  void SetUp() override { std::filesystem::create_directories(dir); }
  void TearDown() override { std::filesystem::remove_all(dir); }
};

Packing two_grains() {
  Packing p;
  p.box = Box{10, 10, true, 0};
  p.position = {Vec2(2, 2), Vec2(5, 5)};
  p.radius = {0.5, 0.6};
  p.fixed = {0, 0};
  return p;
}

template <class F>
void expect_refusal(F&& body, const std::string& path, const std::string& dataset) {
  try {
    body();
    ADD_FAILURE() << "no RuntimeFailure for " << dataset;
  } catch (const RuntimeFailure& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_NE(message.find(dataset), std::string::npos) << message;
  }
}

}  // namespace

TEST_F(FrameCheckTest, PackingWithNonFiniteValuesIsNotWritten) {
  const std::string path = (dir / "packing.h5").string();
  Packing nan_position = two_grains();
  nan_position.position[1].x() = kNaN;
  expect_refusal([&] { write_packing(path, nan_position, io::Parameters{}); }, path, "/particles/grains/position");
  Packing bad_radius = two_grains();
  bad_radius.radius[0] = -0.5;
  expect_refusal([&] { write_packing(path, bad_radius, io::Parameters{}); }, path, "/particles/grains/radius");
  Packing bad_box = two_grains();
  bad_box.box.lx = kNaN;
  expect_refusal([&] { write_packing(path, bad_box, io::Parameters{}); }, path, "/particles/grains/box/edges");
  EXPECT_FALSE(std::filesystem::exists(path));
  write_packing(path, two_grains(), io::Parameters{});  // the same, valid, is written
  EXPECT_TRUE(std::filesystem::exists(path));
}

TEST_F(FrameCheckTest, TrajectoryWriterRefusesNonFiniteFramesAndGrains) {
  const std::string path = (dir / "run.h5").string();
  io::TrajectoryWriter writer(path);
  const io::GrainProperties grains{{0.5, 0.6}, {0.8, 1.1}, {0, 0}};
  io::GrainProperties nan_mass = grains;
  nan_mass.mass[1] = kNaN;
  expect_refusal([&] { writer.write_grains(nan_mass, Box{10, 10, true, 0}); }, path, "/particles/grains/mass");
  writer.write_grains(grains, Box{10, 10, true, 0});
  io::Frame f;
  f.box = Box{10, 10, true, 0};
  f.position = {Vec2(2, 2), Vec2(5, 5)};
  f.velocity = {Vec2(0, 0), Vec2(0, kNaN)};
  f.orientation = {0, 0};
  f.angular_velocity = {0, 0};
  expect_refusal([&] { writer.append_frame(f); }, path, "/particles/grains/velocity");
  f.velocity[1].y() = 0;
  f.has_contacts = true;
  f.contacts.pair = {{0, 1}};
  f.contacts.normal_force = {kNaN};
  f.contacts.tangential_force = {0};
  f.contacts.branch = {Vec2(-3, -3)};
  f.contacts.binary_force = {0};
  f.contacts.pre_normal_velocity = {{0, 0}};
  f.contacts.age = {1};
  expect_refusal([&] { writer.append_frame(f); }, path, "/contacts/normal_force");
  f.contacts.normal_force = {1};
  writer.append_frame(f);
  writer.close();
  EXPECT_EQ(io::TrajectoryReader(path).frame_count(), 1u);
}
