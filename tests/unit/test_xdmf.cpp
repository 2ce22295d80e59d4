// io::xdmf_description on constructed trajectories: each frame's grids name the frame's
// block of every dataset, with the datasets' full shapes, and the forms of frames with no
// contact and with one (docs/programs/gf-xdmf.md). ParaView's reading of such text is
// tested by paraview.GfXdmf.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "io/trajectory.hpp"
#include "io/xdmf.hpp"

namespace fs = std::filesystem;
using namespace granflow;
using namespace granflow::io;

namespace {

constexpr std::size_t kGrains = 5;

class Xdmf : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("granflow_xdmf_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }

  fs::path dir_;
};

// Frame k with `contacts` contacts (i, j) = (c, c + 1), branch (0.1 c, −0.2), forces c + 1.
Frame frame(std::int64_t step, std::size_t contacts, bool periodic_y, bool has_contacts = true) {
  Frame f;
  f.step = step;
  f.time = 0.1 * double(step) + 1.0 / 3.0;
  f.box.lx = 10;
  f.box.ly = 8;
  f.box.periodic_y = periodic_y;
  f.box.offset = periodic_y ? 0.25 * double(step) : 0.0;
  for (std::size_t i = 0; i < kGrains; ++i) {
    f.position.emplace_back(1.0 + double(i), 2.0);
    f.velocity.emplace_back(0.5, -0.5);
    f.orientation.push_back(0.0);
    f.angular_velocity.push_back(0.1);
  }
  f.has_contacts = has_contacts;
  for (std::size_t c = 0; c < contacts; ++c) {
    f.contacts.pair.push_back({std::int32_t(c), std::int32_t(c + 1)});
    f.contacts.normal_force.push_back(double(c + 1));
    f.contacts.tangential_force.push_back(0.0);
    f.contacts.branch.emplace_back(0.1 * double(c), -0.2);
    f.contacts.binary_force.push_back(0.5);
    f.contacts.pre_normal_velocity.push_back({0.0, 0.0});
    f.contacts.age.push_back(1);
  }
  return f;
}

void write(const std::string& path, const std::vector<Frame>& frames) {
  GrainProperties g;
  for (std::size_t i = 0; i < kGrains; ++i) {
    g.radius.push_back(0.5);
    g.mass.push_back(0.785);
    g.fixed.push_back(0);
  }
  TrajectoryWriter writer(path);
  writer.write_grains(g, frames.at(0).box);
  for (const Frame& f : frames) writer.append_frame(f);
  writer.close();
}

std::size_t count(const std::string& text, const std::string& piece) {
  std::size_t n = 0;
  for (auto at = text.find(piece); at != std::string::npos; at = text.find(piece, at + piece.size())) ++n;
  return n;
}

// The selection (start, stride 1, count) of a HyperSlab item followed by its whole dataset.
std::string slab(const std::string& start, const std::string& count, const std::string& dims, const char* type,
                 const std::string& dataset, const std::string& h5 = "t.h5") {
  const std::size_t rank = std::size_t(std::count(start.begin(), start.end(), ' ') + 1);
  std::string stride;
  for (std::size_t r = 0; r < rank; ++r) stride += r ? " 1" : "1";
  return "<DataItem Dimensions=\"3 " + std::to_string(rank) + "\" Format=\"XML\">" + start + " " + stride + " " +
         count + "</DataItem><DataItem Dimensions=\"" + dims + "\" " + type + " Format=\"HDF\">" + h5 + ":" + dataset +
         "</DataItem>";
}

const char* const kDouble = R"(NumberType="Float" Precision="8")";
const char* const kInt32 = R"(NumberType="Int" Precision="4")";

}  // namespace

// Frames of 3, 0, 1 and 4 contacts: rows 0–2, none, 3, 4–7 of the 8 contact rows.
TEST_F(Xdmf, EveryFrameNamesItsBlockOfEveryDataset) {
  const std::string path = file("t.h5");
  write(path, {frame(0, 3, true), frame(10, 0, true), frame(20, 1, true), frame(30, 4, true)});
  XdmfSummary summary;
  const std::string x = xdmf_description(TrajectoryReader(path), "t.h5", &summary);
  EXPECT_EQ(summary.frames, 4u);
  EXPECT_EQ(summary.grains, kGrains);
  EXPECT_EQ(summary.contacts, 8u);

  for (const char* name : {"grains", "contacts", "box"})
    EXPECT_EQ(count(x, "<Grid Name=\"" + std::string(name) + "\" GridType=\"Uniform\">"), 4u) << name;
  EXPECT_EQ(count(x, "<Time Value=\"2.3333333333333335\"/>"), 3u) << "frame 2's time, all 17 digits, in 3 grids";
  for (int k = 0; k < 4; ++k) {
    const std::string K = std::to_string(k);
    EXPECT_NE(x.find(slab(K + " 0 0", "1 5 2", "4 5 2", kDouble, "/particles/grains/position/value")),
              std::string::npos)
        << k;
    EXPECT_NE(x.find(slab(K + " 0", "1 5", "4 5", kDouble, "/particles/grains/angular_velocity/value")),
              std::string::npos)
        << k;
    EXPECT_NE(x.find(slab(K + " 0 0", "1 2 2", "4 2 2", kDouble, "/particles/grains/box/edges/value")),
              std::string::npos)
        << k;
    EXPECT_NE(x.find(slab(K + " 1 0", "1 1 1", "4 2 2", kDouble, "/particles/grains/box/edges/value")),
              std::string::npos)
        << "the offset of frame " << k;
  }
  // Frame 0: rows 0–2; frame 3: rows 4–7 (pair for the connectivity and for the gather).
  for (const auto& [start, rows] : {std::pair<std::string, std::string>{"0", "3"}, {"4", "4"}}) {
    EXPECT_NE(x.find(slab(start + " 0", rows + " 2", "8 2", kInt32, "/contacts/pair")), std::string::npos) << start;
    EXPECT_NE(x.find(slab(start + " 0", rows + " 1", "8 2", kInt32, "/contacts/pair")), std::string::npos) << start;
    EXPECT_NE(x.find(slab(start + " 0", rows + " 1", "8 2", kDouble, "/contacts/branch")), std::string::npos) << start;
    EXPECT_NE(x.find(slab(start + " 1", rows + " 1", "8 2", kDouble, "/contacts/branch")), std::string::npos) << start;
    EXPECT_NE(x.find(slab(start, rows, "8", kDouble, "/contacts/normal_force")), std::string::npos) << start;
    EXPECT_NE(x.find(slab(start, rows, "8", R"(NumberType="Int" Precision="8")", "/contacts/age")), std::string::npos)
        << start;
    EXPECT_NE(x.find("<Topology TopologyType=\"Polyline\" NumberOfElements=\"" + rows + "\" NodesPerElement=\"2\">"),
              std::string::npos);
  }
  EXPECT_EQ(count(x, "Function=\"($0[$1 * 2] , ($0[$1 * 2] - $2)) , ($0[$1 * 2 + 1] , ($0[$1 * 2 + 1] - $3))\""), 2u);
  EXPECT_EQ(count(x, "Function=\"WHERE($0 &gt;= 0)\""), 2u);
  // Frame 1: no cell.
  EXPECT_EQ(count(x, "<Topology TopologyType=\"Polyvertex\" NumberOfElements=\"0\" NodesPerElement=\"1\"/>"), 1u);
  // Frame 2: its one contact (0, 1) in row 3: grain 0's position in frame 2, branch row 3.
  EXPECT_EQ(count(x, "Function=\"$0 ; ($0 - $1)\""), 1u);
  EXPECT_NE(x.find(slab("2 0 0", "1 1 2", "4 5 2", kDouble, "/particles/grains/position/value") +
                   "</DataItem><DataItem ItemType=\"HyperSlab\" Dimensions=\"2\" " + kDouble + ">" +
                   slab("3 0", "1 2", "8 2", kDouble, "/contacts/branch")),
            std::string::npos);
  EXPECT_NE(x.find(slab("3", "1", "8", kDouble, "/contacts/binary_force")), std::string::npos);
}

// The single contact of a frame names the position of its grain i (here 2 of (2, 3)).
TEST_F(Xdmf, OneContactNamesItsFirstGrain) {
  const std::string path = file("t.h5");
  Frame one = frame(10, 3, true);
  for (auto* column : {&one.contacts.normal_force, &one.contacts.tangential_force, &one.contacts.binary_force})
    column->erase(column->begin(), column->begin() + 2);
  one.contacts.pair.erase(one.contacts.pair.begin(), one.contacts.pair.begin() + 2);
  one.contacts.branch.erase(one.contacts.branch.begin(), one.contacts.branch.begin() + 2);
  one.contacts.pre_normal_velocity.erase(one.contacts.pre_normal_velocity.begin(),
                                         one.contacts.pre_normal_velocity.begin() + 2);
  one.contacts.age.erase(one.contacts.age.begin(), one.contacts.age.begin() + 2);
  write(path, {frame(0, 2, true), one});
  const std::string x = xdmf_description(TrajectoryReader(path), "t.h5");
  EXPECT_NE(x.find(slab("1 2 0", "1 1 2", "2 5 2", kDouble, "/particles/grains/position/value")), std::string::npos);
  EXPECT_NE(x.find(slab("2 0", "1 2", "3 2", kDouble, "/contacts/branch")), std::string::npos);
}

// Without /contacts (a packing, or frames written without contacts): grains and box only. An
// incline box (open in y) is drawn the same way.
TEST_F(Xdmf, NoContactsGroupNoContactsCollection) {
  const std::string path = file("p.h5");
  write(path, {frame(0, 0, false, false)});
  const std::string x = xdmf_description(TrajectoryReader(path), "p.h5");
  EXPECT_EQ(x.find("contacts"), std::string::npos);
  EXPECT_EQ(count(x, "<Grid Name=\"grains\" GridType=\"Uniform\">"), 1u);
  EXPECT_EQ(count(x, "<Grid Name=\"box\" GridType=\"Uniform\">"), 1u);
}

// The trajectory's name is written as XML text (escaped), as given.
TEST_F(Xdmf, NameIsEscaped) {
  const std::string path = file("t.h5");
  write(path, {frame(0, 2, true)});
  const std::string x = xdmf_description(TrajectoryReader(path), "runs/a&b<1>.h5");
  EXPECT_NE(x.find(">runs/a&amp;b&lt;1&gt;.h5:/particles/grains/position/value<"), std::string::npos);
  EXPECT_EQ(x.find("a&b"), std::string::npos);
}
