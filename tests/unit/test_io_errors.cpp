// Bad trajectory files and misuse of the writer: every error is one line naming the
// file, of the type that gives the right exit code, and leaks no HDF5 object.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>

#include "io/hdf5_handle.hpp"
#include "io/trajectory.hpp"

namespace fs = std::filesystem;
using namespace granflow;
using namespace granflow::io;

namespace {

class IoErrorTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("granflow_io_" + std::string(info->test_suite_name()) + "_" + info->name() +
                                        "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    EXPECT_EQ(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0) << "HDF5 objects left open";
    fs::remove_all(dir_);
  }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }

  // A valid trajectory of n grains and `frames` frames.
  std::string valid(const std::string& name, std::size_t n = 4, int frames = 1) const {
    std::string path = file(name);
    TrajectoryWriter writer(path);
    Frame f;
    f.box.lx = f.box.ly = 10;
    f.position.assign(n, Vec2(1, 2));
    f.velocity.assign(n, Vec2(0.5, -0.5));
    f.orientation.assign(n, 0.1);
    f.angular_velocity.assign(n, 0.2);
    writer.write_grains({std::vector<double>(n, 0.7), std::vector<double>(n, 1.5), std::vector<std::uint8_t>(n, 0)},
                        f.box);
    for (int k = 0; k < frames; ++k) {
      f.step = k;
      writer.append_frame(f);
    }
    writer.close();
    return path;
  }

  fs::path dir_;
};
using IoReaderErrors = IoErrorTest;
using IoWriterErrors = IoErrorTest;
using IoHandle = IoErrorTest;

// Runs body, expecting exception E with a one-line message naming path and saying what.
template <class E>
void expect_error(const std::function<void()>& body, const std::string& path, const std::string& what) {
  try {
    body();
    ADD_FAILURE() << "no exception; expected one naming " << path;
  } catch (const E& e) {
    std::string message = e.what();
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_NE(message.find(what), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << "not one line: " << message;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "wrong exception type: " << e.what();
  }
}

void open_reader(const std::string& path) { TrajectoryReader reader(path); }

// Replaces a dataset of a valid file by one of another shape.
void replace_dataset(const std::string& path, const std::string& name, std::vector<hsize_t> dims) {
  hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  ASSERT_GE(H5Ldelete(f, name.c_str(), H5P_DEFAULT), 0);
  hid_t space = H5Screate_simple(int(dims.size()), dims.data(), nullptr);
  hid_t d = H5Dcreate2(f, name.c_str(), H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(d, 0);
  H5Dclose(d);
  H5Sclose(space);
  H5Fclose(f);
}

TEST_F(IoReaderErrors, MissingFile) {
  std::string path = file("nowhere.h5");
  expect_error<UsageError>([&] { open_reader(path); }, path, "no such file");
}

TEST_F(IoReaderErrors, Directory) {
  expect_error<UsageError>([&] { open_reader(dir_.string()); }, dir_.string(), "directory");
}

TEST_F(IoReaderErrors, TextFileNamedH5) {
  std::string path = file("notes.h5");
  std::ofstream(path) << "these are not the grains you are looking for\n";
  expect_error<UsageError>([&] { open_reader(path); }, path, "not an HDF5 file");
}

TEST_F(IoReaderErrors, TruncatedFile) {
  std::string good = valid("good.h5", 500, 5), path = file("cut.h5");
  std::ifstream in(good, std::ios::binary);
  std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  ASSERT_GT(bytes.size(), 10000u);
  std::ofstream(path, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  expect_error<UsageError>([&] { open_reader(path); }, path, "truncated");
}

TEST_F(IoReaderErrors, HdfFileWithoutH5md) {
  std::string path = file("plain.h5");
  H5Fclose(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT));
  expect_error<UsageError>([&] { open_reader(path); }, path, "no group /h5md");
}

TEST_F(IoReaderErrors, HdfFileWithoutGrains) {
  std::string path = file("nograins.h5");
  TrajectoryWriter(path).close();  // /h5md only
  expect_error<UsageError>([&] { open_reader(path); }, path, "no group /particles/grains");
}

TEST_F(IoReaderErrors, PositionOfWrongRank) {
  std::string path = valid("rank.h5", 4, 2);
  replace_dataset(path, "/particles/grains/position/value", {2, 8});
  expect_error<UsageError>([&] { open_reader(path); }, path,
                           "/particles/grains/position/value has shape [2][8] but must be [frames][grains][2]");
}

TEST_F(IoReaderErrors, VelocityOfOtherGrainCount) {
  std::string path = valid("velocity.h5", 4, 2);
  replace_dataset(path, "/particles/grains/velocity/value", {2, 5, 2});
  expect_error<UsageError>([&] { open_reader(path); }, path, "/particles/grains/velocity/value has shape [2][5][2]");
}

TEST_F(IoReaderErrors, MissingRadius) {
  std::string path = valid("radius.h5");
  hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  H5Ldelete(f, "/particles/grains/radius", H5P_DEFAULT);
  H5Fclose(f);
  expect_error<UsageError>([&] { open_reader(path); }, path, "missing dataset /particles/grains/radius");
}

TEST_F(IoReaderErrors, FrameOutOfRangeNamesTheCount) {
  std::string path = valid("frames.h5", 4, 3);
  TrajectoryReader reader(path);
  expect_error<UsageError>([&] { reader.frame(3); }, path, "the file has 3 frames");
  expect_error<UsageError>([&] { reader.box(7); }, path, "the file has 3 frames");
  expect_error<UsageError>([&] { reader.observable_scalar("pressure"); }, path, "no observable 'pressure'");
}

TEST_F(IoReaderErrors, ReopenOfBadFileIsUsageError) {
  std::string path = file("notes.h5");
  std::ofstream(path) << "text\n";
  expect_error<UsageError>([&] { TrajectoryWriter::reopen_for_append(path, 0, 0); }, path, "not an HDF5 file");
}

TEST_F(IoWriterErrors, UnwritableDirectory) {
  std::string path = file("missing/dir/out.h5");
  expect_error<RuntimeFailure>([&] { TrajectoryWriter writer(path); }, path, "cannot create HDF5 file");
}

TEST_F(IoWriterErrors, MisuseIsARuntimeFailure) {
  std::string path = file("misuse.h5");
  TrajectoryWriter writer(path);
  Frame f;
  f.box.lx = f.box.ly = 5;
  f.position.assign(2, Vec2(1, 1));
  f.velocity.assign(2, Vec2(0, 0));
  f.orientation.assign(2, 0.0);
  f.angular_velocity.assign(2, 0.0);
  expect_error<RuntimeFailure>([&] { writer.append_frame(f); }, path, "before write_grains");
  GrainProperties grains{{0.5, 0.5}, {1, 1}, {0, 0}};
  expect_error<RuntimeFailure>([&] { writer.write_grains({{}, {}, {}}, f.box); }, path, "at least one grain");
  expect_error<RuntimeFailure>([&] { writer.write_grains({{0.5, 0.5}, {1}, {0, 0}}, f.box); }, path, "different sizes");
  writer.write_grains(grains, f.box);
  expect_error<RuntimeFailure>([&] { writer.write_grains(grains, f.box); }, path, "grains written twice");

  Frame short_frame = f;
  short_frame.velocity.pop_back();
  expect_error<RuntimeFailure>([&] { writer.append_frame(short_frame); }, path, "velocity has 1 entries, expected 2");
  Frame bad_pair = f;
  bad_pair.has_contacts = true;
  bad_pair.contacts.pair.push_back({0, 2});
  bad_pair.contacts.normal_force.push_back(1);
  bad_pair.contacts.tangential_force.push_back(0);
  bad_pair.contacts.branch.emplace_back(1, 0);
  bad_pair.contacts.binary_force.push_back(0);
  bad_pair.contacts.pre_normal_velocity.push_back({0, 0});
  bad_pair.contacts.age.push_back(0);
  expect_error<RuntimeFailure>([&] { writer.append_frame(bad_pair); }, path, "contact pair (0, 2)");
  bad_pair.contacts.age.clear();
  expect_error<RuntimeFailure>([&] { writer.append_frame(bad_pair); }, path, "contacts age has 0 entries");
  Frame open_box = f;
  open_box.box.periodic_y = false;
  expect_error<RuntimeFailure>([&] { writer.append_frame(open_box); }, path, "boundary");

  writer.append_frame(f);
  expect_error<RuntimeFailure>([&] { writer.append_frame(f); }, path, "frame step 0 after step 0");
  writer.close();
  writer.close();  // closing twice is harmless
  expect_error<RuntimeFailure>([&] { writer.append_frame(f); }, path, "after close()");
  expect_error<RuntimeFailure>([&] { writer.flush(); }, path, "after close()");
}

TEST_F(IoHandle, ErrorsNameFileAndObject) {
  std::string path = file("handle.h5");
  File f = create_file(path);
  Group g = create_group(f.get(), "particles");
  expect_error<Hdf5Error>([&] { open_dataset(g.get(), "position"); }, path, "/particles: open dataset position: ");
  expect_error<Hdf5Error>([&] { open_group(f.get(), "/nowhere"); }, path, "open group /nowhere");
  EXPECT_FALSE(exists(f.get(), "/particles/grains/position"));
  EXPECT_TRUE(exists(f.get(), "particles"));
}

TEST_F(IoHandle, HandlesCloseWhenMovedAndDestroyed) {
  std::string path = file("handle.h5");
  {
    File f = create_file(path);
    Group a = create_group(f.get(), "a");
    Group b = std::move(a);
    EXPECT_FALSE(a);
    EXPECT_TRUE(b);
    EXPECT_EQ(H5Fget_obj_count(f.get(), H5F_OBJ_GROUP), 1);
    b = create_group(f.get(), "b");  // move-assignment closes the old group
    EXPECT_EQ(H5Fget_obj_count(f.get(), H5F_OBJ_GROUP), 1);
  }
  EXPECT_EQ(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0);
}

}  // namespace

// A chunk overwritten in place (what a power loss or a disk error can leave) is
// found by reading every dataset, though the file opens and its shapes are right.
TEST_F(IoReaderErrors, OverwrittenChunkIsFoundByReadingEveryDataset) {
  const std::string path = valid("chunk.h5", 64, 12);
  read_every_dataset(open_file(path, false).get());  // the intact file reads whole

  haddr_t offset = 0;
  hsize_t size = 0;
  {
    File f = open_file(path, false);
    Dataset d = open_dataset(f.get(), "/particles/grains/position/value");
    Dataspace space(H5Dget_space(d.get()));
    unsigned filter_mask = 0;
    std::vector<hsize_t> chunk_offset(3, 0);
    ASSERT_GE(H5Dget_chunk_info(d.get(), space.get(), 0, chunk_offset.data(), &filter_mask, &offset, &size), 0);
  }
  ASSERT_GT(size, 16u);
  {
    std::fstream out(path, std::ios::in | std::ios::out | std::ios::binary);
    out.seekp(std::streamoff(offset + size / 2));
    const std::string garbage(8, '\x5a');
    out.write(garbage.data(), std::streamsize(garbage.size()));
  }
  try {
    read_every_dataset(open_file(path, false).get());
    FAIL() << "an overwritten chunk was read without error";
  } catch (const Hdf5Error& e) {
    EXPECT_NE(std::string(e.what()).find("/particles/grains/position/value"), std::string::npos) << e.what();
  }
}
