// HDF5 trajectory I/O: round trips of every field, the H5MD layout seen through the
// plain HDF5 API and h5dump, observables across buffer flushes, resume by
// reopen_for_append, and byte-identical output for identical input.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <thread>

#include "core/random.hpp"
#include "core/version.hpp"
#include "io/hdf5_handle.hpp"
#include "io/trajectory.hpp"
#include "unit/expect_frame.hpp"

namespace fs = std::filesystem;
using namespace granflow;
using namespace granflow::io;
using granflow::test_support::expect_same_frame;

namespace {

class IoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("granflow_io_" + std::string(info->test_suite_name()) + "_" + info->name() +
                                        "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }

  fs::path dir_;
};
using IoRoundTrip = IoTest;
using IoLayout = IoTest;
using IoParameters = IoTest;
using IoObservables = IoTest;
using IoReopen = IoTest;
using IoDeterminism = IoTest;

GrainProperties make_grains(std::size_t n, std::uint64_t seed) {
  Rng rng(seed);
  GrainProperties g;
  for (std::size_t i = 0; i < n; ++i) {
    double r = rng.uniform(0.5, 0.9);
    g.radius.push_back(r);
    g.mass.push_back(M_PI * r * r);
    g.fixed.push_back(i % 3 == 0 ? 1 : 0);
  }
  return g;
}

Frame make_frame(std::size_t n, std::int64_t step, std::size_t contacts, bool periodic_y, std::uint64_t seed,
                 bool has_contacts = true) {
  Rng rng(seed);
  Frame f;
  f.step = step;
  f.time = 0.01 * double(step) + 1e-3;
  f.box.lx = 20.5;
  f.box.ly = 17.25;
  f.box.periodic_y = periodic_y;
  f.box.offset = periodic_y ? rng.uniform(0, f.box.lx) : 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    f.position.emplace_back(rng.uniform(0, f.box.lx), rng.uniform(0, f.box.ly));
    f.velocity.emplace_back(rng.normal(), rng.normal());
    f.orientation.push_back(rng.uniform(-M_PI, M_PI));
    f.angular_velocity.push_back(rng.normal());
  }
  f.has_contacts = has_contacts;
  for (std::size_t c = 0; has_contacts && c < contacts; ++c) {
    auto& k = f.contacts;
    k.pair.push_back({std::int32_t(rng.bits() % n), std::int32_t(rng.bits() % n)});
    k.normal_force.push_back(rng.uniform(0, 5));
    k.tangential_force.push_back(rng.normal());
    k.branch.emplace_back(rng.normal(), rng.normal());
    k.binary_force.push_back(rng.uniform(0, 1));
    k.pre_normal_velocity.push_back({rng.normal(), rng.normal()});
    k.age.push_back(std::int64_t(rng.bits() % 1000));
  }
  return f;
}

// ---- raw HDF5 access, to check the layout independently of the reader ----

struct RawFile {
  hid_t id;
  explicit RawFile(const std::string& path) : id(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT)) {
    EXPECT_GE(id, 0) << path;
  }
  ~RawFile() { H5Fclose(id); }
};

std::vector<hsize_t> raw_shape(hid_t file, const std::string& name) {
  hid_t d = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  EXPECT_GE(d, 0) << name;
  hid_t s = H5Dget_space(d);
  std::vector<hsize_t> dims(static_cast<std::size_t>(H5Sget_simple_extent_ndims(s)));
  H5Sget_simple_extent_dims(s, dims.data(), nullptr);
  H5Sclose(s);
  H5Dclose(d);
  return dims;
}

template <class T>
std::vector<T> raw_read(hid_t file, const std::string& name, hid_t mem_type) {
  std::size_t n = 1;
  for (hsize_t d : raw_shape(file, name)) n *= d;
  std::vector<T> values(n);
  hid_t d = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  EXPECT_GE(H5Dread(d, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), 0) << name;
  H5Dclose(d);
  return values;
}

// Every dataset of a file: path -> (shape, bytes in the native form of its type).
using DatasetContents = std::map<std::string, std::pair<std::vector<hsize_t>, std::string>>;

void collect(hid_t group, const std::string& prefix, DatasetContents& out) {
  H5G_info_t info;
  H5Gget_info(group, &info);
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    char name[256];
    H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, i, name, sizeof name, H5P_DEFAULT);
    hid_t object = H5Oopen(group, name, H5P_DEFAULT);
    std::string path = prefix + "/" + name;
    if (H5Iget_type(object) == H5I_GROUP) {
      collect(object, path, out);
    } else {
      hid_t type = H5Dget_type(object);
      hid_t native = H5Tget_native_type(type, H5T_DIR_DEFAULT);
      hid_t space = H5Dget_space(object);
      std::vector<hsize_t> dims(static_cast<std::size_t>(H5Sget_simple_extent_ndims(space)));
      H5Sget_simple_extent_dims(space, dims.data(), nullptr);
      std::string bytes(std::size_t(H5Sget_simple_extent_npoints(space)) * H5Tget_size(native), '\0');
      if (!bytes.empty()) H5Dread(object, native, H5S_ALL, H5S_ALL, H5P_DEFAULT, bytes.data());
      out[path] = {dims, bytes};
      H5Sclose(space);
      H5Tclose(native);
      H5Tclose(type);
    }
    H5Oclose(object);
  }
}

DatasetContents all_datasets(const std::string& path) {
  RawFile f(path);
  DatasetContents out;
  collect(f.id, "", out);
  return out;
}

// Every dataset of `path` has the shape and the bytes it has in `expected`, and no other.
void expect_datasets(const std::string& path, const DatasetContents& expected) {
  DatasetContents got = all_datasets(path);
  ASSERT_EQ(got.size(), expected.size());
  for (const auto& [name, contents] : expected) {
    ASSERT_TRUE(got.contains(name)) << name;
    EXPECT_EQ(got[name].first, contents.first) << name;
    EXPECT_TRUE(got[name].second == contents.second) << name << " differs";
  }
}

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// ---- round trips ----

void round_trip(const std::string& path, bool periodic_y) {
  const std::size_t n = 37;
  GrainProperties grains = make_grains(n, 1);
  // Contact counts differ from frame to frame, one frame has none.
  std::vector<Frame> frames{make_frame(n, 0, 12, periodic_y, 2), make_frame(n, 100, 0, periodic_y, 3),
                            make_frame(n, 250, 5, periodic_y, 4), make_frame(n, 400, 7, periodic_y, 5)};
  {
    TrajectoryWriter writer(path, "tester");
    writer.write_grains(grains, frames[0].box);
    if (periodic_y) writer.set_lees_edwards_rate(0.125);
    for (const Frame& f : frames) writer.append_frame(f);
    EXPECT_EQ(writer.frame_count(), 4u);
    writer.close();
  }
  TrajectoryReader reader(path);
  EXPECT_EQ(reader.path(), path);
  ASSERT_EQ(reader.frame_count(), 4u);
  ASSERT_EQ(reader.grain_count(), n);
  EXPECT_TRUE(reader.has_contacts());
  GrainProperties g = reader.grains();
  EXPECT_EQ(g.radius, grains.radius);
  EXPECT_EQ(g.mass, grains.mass);
  EXPECT_EQ(g.fixed, grains.fixed);
  EXPECT_EQ(reader.lees_edwards_rate(), periodic_y ? 0.125 : 0.0);
  EXPECT_EQ(reader.frame_steps(), (std::vector<std::int64_t>{0, 100, 250, 400}));
  EXPECT_EQ(reader.frame_times(),
            (std::vector<double>{frames[0].time, frames[1].time, frames[2].time, frames[3].time}));
  // Read out of order: each frame is read on its own.
  for (std::size_t k : {2u, 0u, 3u, 1u}) {
    SCOPED_TRACE("frame " + std::to_string(k));
    expect_same_frame(reader.frame(k), frames[k]);
    Box b = reader.box(k);
    EXPECT_EQ(b.offset, frames[k].box.offset);
    EXPECT_EQ(b.periodic_y, periodic_y);
  }
  EXPECT_EQ(reader.frame(1).contacts.size(), 0u);
  EXPECT_EQ(reader.frame(3).contacts.size(), 7u);
}

TEST_F(IoRoundTrip, PeriodicBox) { round_trip(file("periodic.h5"), true); }

TEST_F(IoRoundTrip, OpenBox) {
  std::string path = file("open.h5");
  round_trip(path, false);
  RawFile f(path);
  EXPECT_EQ(H5Lexists(f.id, "/lees_edwards", H5P_DEFAULT), 0) << "no Lees–Edwards state for an open box";
}

TEST_F(IoRoundTrip, OpenBoxRefusesShearRate) {
  TrajectoryWriter writer(file("open.h5"));
  Frame f = make_frame(4, 0, 0, false, 1);
  writer.write_grains(make_grains(4, 1), f.box);
  EXPECT_THROW(writer.set_lees_edwards_rate(1.0), RuntimeFailure);
}

TEST_F(IoRoundTrip, ContactsRecordedFromALaterFrame) {
  std::string path = file("late.h5");
  const std::size_t n = 10;
  std::vector<Frame> frames{make_frame(n, 1, 4, true, 1, false), make_frame(n, 2, 4, true, 2, false),
                            make_frame(n, 3, 6, true, 3), make_frame(n, 4, 2, true, 4, false)};
  {
    TrajectoryWriter writer(path);
    writer.write_grains(make_grains(n, 1), frames[0].box);
    for (const Frame& f : frames) writer.append_frame(f);
  }  // the destructor closes
  TrajectoryReader reader(path);
  ASSERT_TRUE(reader.has_contacts());
  for (std::size_t k = 0; k < frames.size(); ++k) expect_same_frame(reader.frame(k), frames[k]);
  RawFile f(path);
  EXPECT_EQ(raw_read<std::int64_t>(f.id, "/contacts/frame_offset", H5T_NATIVE_INT64),
            (std::vector<std::int64_t>{0, 0, 0, 6, 6}));
}

TEST_F(IoRoundTrip, PackingWithoutContacts) {
  std::string path = file("packing.h5");
  Frame f = make_frame(8, 0, 3, true, 5, false);
  Parameters p;
  p.set("packing_fraction", 0.8);
  write_packing(path, f, make_grains(8, 2), p);
  TrajectoryReader reader(path);
  EXPECT_EQ(reader.frame_count(), 1u);
  EXPECT_FALSE(reader.has_contacts());
  Frame r = reader.frame(0);
  EXPECT_FALSE(r.has_contacts);
  expect_same_frame(r, f);
  EXPECT_EQ(reader.parameters().get_double("packing_fraction"), 0.8);
  RawFile raw(path);
  EXPECT_EQ(H5Lexists(raw.id, "/contacts", H5P_DEFAULT), 0);
}

TEST_F(IoLayout, LeesEdwardsOffsetInEdges) {
  std::string path = file("le.h5");
  const std::size_t n = 5;
  std::vector<Frame> frames{make_frame(n, 0, 0, true, 1), make_frame(n, 7, 0, true, 2)};
  frames[0].box.offset = 0.0;
  frames[1].box.offset = 3.75;
  {
    TrajectoryWriter writer(path);
    writer.write_grains(make_grains(n, 1), frames[0].box);
    writer.set_lees_edwards_rate(2.5e-3);
    for (const Frame& f : frames) writer.append_frame(f);
  }
  RawFile f(path);
  EXPECT_EQ(raw_shape(f.id, "/particles/grains/box/edges/value"), (std::vector<hsize_t>{2, 2, 2}));
  EXPECT_EQ(raw_read<double>(f.id, "/particles/grains/box/edges/value", H5T_NATIVE_DOUBLE),
            (std::vector<double>{20.5, 0, 0.0, 17.25, 20.5, 0, 3.75, 17.25}));
  EXPECT_EQ(raw_read<double>(f.id, "/lees_edwards/offset/value", H5T_NATIVE_DOUBLE), (std::vector<double>{0.0, 3.75}));
  EXPECT_EQ(raw_read<std::int64_t>(f.id, "/lees_edwards/offset/step", H5T_NATIVE_INT64),
            (std::vector<std::int64_t>{0, 7}));
  hid_t le = H5Gopen2(f.id, "/lees_edwards", H5P_DEFAULT);
  hid_t rate = H5Aopen(le, "rate", H5P_DEFAULT);
  double value = 0;
  H5Aread(rate, H5T_NATIVE_DOUBLE, &value);
  EXPECT_EQ(value, 2.5e-3);
  H5Aclose(rate);
  H5Gclose(le);
  EXPECT_EQ(TrajectoryReader(path).box(1).offset, 3.75);
}

// ---- H5MD layout, as standard tools see it ----

std::string read_string_attribute(hid_t object, const char* name, bool* variable_length = nullptr) {
  hid_t a = H5Aopen(object, name, H5P_DEFAULT);
  hid_t t = H5Aget_type(a);
  EXPECT_EQ(H5Tget_class(t), H5T_STRING) << name;
  if (variable_length) *variable_length = H5Tis_variable_str(t) > 0;
  std::string s(H5Tget_size(t), '\0');
  H5Aread(a, t, s.data());
  s.resize(std::min(s.find('\0'), s.size()));
  H5Tclose(t);
  H5Aclose(a);
  return s;
}

TEST_F(IoLayout, FollowsH5md) {
  std::string path = file("h5md.h5");
  const std::size_t n = 6;
  {
    TrajectoryWriter writer(path, "A. Tester");
    Frame f = make_frame(n, 0, 2, true, 1);
    writer.write_grains(make_grains(n, 1), f.box);
    writer.append_frame(f);
    writer.append_observable("pressure", 0, 0.0, 1.5);
  }
  RawFile f(path);
  hid_t h5md = H5Gopen2(f.id, "/h5md", H5P_DEFAULT);
  ASSERT_GE(h5md, 0);
  hid_t version = H5Aopen(h5md, "version", H5P_DEFAULT);
  hid_t version_type = H5Aget_type(version);
  EXPECT_EQ(H5Tget_class(version_type), H5T_INTEGER);
  EXPECT_EQ(H5Tget_size(version_type), 4u);
  std::int32_t v[2] = {0, 0};
  H5Aread(version, H5T_NATIVE_INT32, v);
  EXPECT_EQ(v[0], 1);
  EXPECT_EQ(v[1], 1);
  H5Tclose(version_type);
  H5Aclose(version);
  hid_t author = H5Gopen2(h5md, "author", H5P_DEFAULT);
  EXPECT_EQ(read_string_attribute(author, "name"), "A. Tester");
  hid_t creator = H5Gopen2(h5md, "creator", H5P_DEFAULT);
  bool variable = true;
  EXPECT_EQ(read_string_attribute(creator, "name", &variable), "granflow");
  EXPECT_FALSE(variable) << "H5MD 1.1 strings are fixed-length";
  EXPECT_EQ(read_string_attribute(creator, "version"), granflow::version());
  H5Gclose(creator);
  H5Gclose(author);
  H5Gclose(h5md);

  hid_t box = H5Gopen2(f.id, "/particles/grains/box", H5P_DEFAULT);
  hid_t dimension = H5Aopen(box, "dimension", H5P_DEFAULT);
  hid_t dimension_space = H5Aget_space(dimension);
  EXPECT_EQ(H5Sget_simple_extent_type(dimension_space), H5S_SCALAR);
  std::int32_t d = 0;
  H5Aread(dimension, H5T_NATIVE_INT32, &d);
  EXPECT_EQ(d, 2);
  H5Sclose(dimension_space);
  H5Aclose(dimension);
  hid_t boundary = H5Aopen(box, "boundary", H5P_DEFAULT);
  hid_t boundary_type = H5Aget_type(boundary);
  EXPECT_FALSE(H5Tis_variable_str(boundary_type) > 0);
  std::size_t width = H5Tget_size(boundary_type);
  std::string both(2 * width, '\0');
  H5Aread(boundary, boundary_type, both.data());
  EXPECT_EQ(both.substr(0, 8), "periodic");
  EXPECT_EQ(both.substr(width, 8), "periodic");
  H5Tclose(boundary_type);
  H5Aclose(boundary);
  H5Gclose(box);

  EXPECT_EQ(raw_shape(f.id, "/particles/grains/position/value"), (std::vector<hsize_t>{1, n, 2}));
  EXPECT_EQ(raw_shape(f.id, "/particles/grains/orientation/value"), (std::vector<hsize_t>{1, n}));
  EXPECT_EQ(raw_shape(f.id, "/particles/grains/radius"), (std::vector<hsize_t>{n}));
  EXPECT_EQ(raw_shape(f.id, "/contacts/pair"), (std::vector<hsize_t>{2, 2}));
  EXPECT_EQ(raw_shape(f.id, "/observables/pressure/value"), (std::vector<hsize_t>{1}));

  // Time-dependent data is chunked, shuffled and deflated.
  hid_t position = H5Dopen2(f.id, "/particles/grains/position/value", H5P_DEFAULT);
  hid_t dcpl = H5Dget_create_plist(position);
  EXPECT_EQ(H5Pget_layout(dcpl), H5D_CHUNKED);
  ASSERT_EQ(H5Pget_nfilters(dcpl), 2);
  unsigned flags = 0, level = 0;
  std::size_t nvalues = 1;
  EXPECT_EQ(H5Pget_filter2(dcpl, 0, &flags, &nvalues, &level, 0, nullptr, nullptr), H5Z_FILTER_SHUFFLE);
  nvalues = 1;
  EXPECT_EQ(H5Pget_filter2(dcpl, 1, &flags, &nvalues, &level, 0, nullptr, nullptr), H5Z_FILTER_DEFLATE);
  EXPECT_EQ(level, 4u);
  H5Pclose(dcpl);
  H5Dclose(position);
}

TEST_F(IoLayout, ReadableByH5dump) {
  if (std::system("command -v h5dump > /dev/null 2>&1") != 0) GTEST_SKIP() << "h5dump not installed";
  std::string path = file("dump.h5"), out = file("dump.txt");
  Frame f = make_frame(3, 0, 1, true, 1);
  Parameters p;
  p.set("seed", 7);
  write_packing(path, f, make_grains(3, 1), p);
  ASSERT_EQ(std::system(("h5dump -H '" + path + "' > '" + out + "' 2>&1").c_str()), 0) << file_bytes(out);
  std::string header = file_bytes(out);
  EXPECT_NE(header.find("GROUP \"particles\""), std::string::npos);
  EXPECT_NE(header.find("DATASET \"value\""), std::string::npos);
  ASSERT_EQ(std::system(("h5dump -a /h5md/version '" + path + "' > '" + out + "' 2>&1").c_str()), 0);
  EXPECT_NE(file_bytes(out).find("(0): 1, 1"), std::string::npos) << file_bytes(out);
}

// ---- parameters ----

TEST_F(IoParameters, AllThreeTypes) {
  std::string path = file("params.h5");
  std::string long_command(100000, 'x');  // beyond HDF5's 64 KiB compact-attribute limit
  Parameters p;
  p.set("rate", 1e-3);
  p.set("seed", std::int64_t{1234567890123});
  p.set("grains", 400);  // an int
  p.set("quiet", true);
  p.set("program", "gf-shear");
  p.set("command_line", long_command);
  p.set("label", std::string("ν=0.80 μ=0.5"));
  p.set("empty", std::string());
  write_packing(path, make_frame(2, 0, 0, true, 1), make_grains(2, 1), p);

  // The attributes have native HDF5 types.
  {
    RawFile f(path);
    hid_t group = H5Gopen2(f.id, "/parameters", H5P_DEFAULT);
    auto type_of = [&](const char* name) {
      hid_t a = H5Aopen(group, name, H5P_DEFAULT);
      hid_t t = H5Aget_type(a);
      auto result = std::make_pair(H5Tget_class(t), H5Tget_size(t));
      H5Tclose(t);
      H5Aclose(a);
      return result;
    };
    EXPECT_EQ(type_of("rate"), std::make_pair(H5T_FLOAT, std::size_t{8}));
    EXPECT_EQ(type_of("seed"), std::make_pair(H5T_INTEGER, std::size_t{8}));
    EXPECT_EQ(type_of("grains"), std::make_pair(H5T_INTEGER, std::size_t{8}));
    bool variable = true;
    EXPECT_EQ(read_string_attribute(group, "program", &variable), "gf-shear");
    EXPECT_FALSE(variable);
    H5Gclose(group);
  }

  Parameters q = TrajectoryReader(path).parameters();
  EXPECT_EQ(q.items(), p.items());
  EXPECT_EQ(q.get_double("rate"), 1e-3);
  EXPECT_EQ(q.get_int("seed"), 1234567890123);
  EXPECT_EQ(q.get_int("grains"), 400);
  EXPECT_EQ(q.get_double("grains"), 400.0);
  EXPECT_EQ(q.get_int("quiet"), 1);
  EXPECT_EQ(q.get_string("program"), "gf-shear");
  EXPECT_EQ(q.get_string("command_line"), long_command);
  EXPECT_EQ(q.get_string("label"), "ν=0.80 μ=0.5");
  EXPECT_EQ(q.get_string("empty"), "");
  EXPECT_TRUE(q.has("seed"));
  EXPECT_FALSE(q.has("friction"));
}

TEST_F(IoParameters, RewrittenValuesReplaceOldOnes) {
  std::string path = file("params.h5");
  {
    TrajectoryWriter writer(path);
    Parameters p;
    p.set("rate", 1.0);
    p.set("seed", 1);
    writer.write_parameters(p);
    Parameters q;
    q.set("rate", std::string("fast"));  // a new type under the same name
    writer.write_parameters(q);
    Frame f = make_frame(2, 0, 0, true, 1);
    writer.write_grains(make_grains(2, 1), f.box);
    writer.append_frame(f);
  }
  Parameters r = TrajectoryReader(path).parameters();
  EXPECT_EQ(r.get_string("rate"), "fast");
  EXPECT_EQ(r.get_int("seed"), 1);
}

TEST_F(IoParameters, ErrorsNameTheFile) {
  std::string path = file("params.h5");
  Parameters p;
  p.set("rate", 1e-3);
  p.set("program", "gf-shear");
  write_packing(path, make_frame(2, 0, 0, true, 1), make_grains(2, 1), p);
  Parameters q = TrajectoryReader(path).parameters();
  for (auto get : std::vector<std::function<void()>>{[&] { q.get_double("friction"); }, [&] { q.get_int("rate"); },
                                                     [&] { q.get_string("rate"); }, [&] { q.get_double("program"); }}) {
    try {
      get();
      ADD_FAILURE() << "no UsageError";
    } catch (const UsageError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(Parameters().get_int("seed"), UsageError);
}

// ---- observables ----

Mat2 tensor(int i) {
  Mat2 m;
  m << 1.0 * i, 2.0 * i + 0.5, -3.0 * i, 0.25 * i;  // asymmetric: catches transposes
  return m;
}

// A minimal trajectory to hang observables on.
TrajectoryWriter writer_with_one_frame(const std::string& path) {
  TrajectoryWriter writer(path);
  Frame f = make_frame(3, 0, 0, true, 1);
  writer.write_grains(make_grains(3, 1), f.box);
  writer.append_frame(f);
  return writer;
}

TEST_F(IoObservables, AcrossBufferFlushes) {
  std::string path = file("obs.h5");
  const int rows = 10000;
  {
    TrajectoryWriter writer = writer_with_one_frame(path);
    for (int i = 0; i < rows; ++i) {
      writer.append_observable("pressure", i, 0.5 * i, std::sin(i));
      if (i % 2 == 0) writer.append_observable("stress_static", i, 0.5 * i, tensor(i));
      if (i == 5000) writer.flush();  // an explicit flush in the middle of a block
    }
    writer.close();
  }
  TrajectoryReader reader(path);
  EXPECT_EQ(reader.observable_names(), (std::vector<std::string>{"pressure", "stress_static"}));
  EXPECT_TRUE(reader.has_observable("pressure"));
  EXPECT_FALSE(reader.has_observable("temperature"));
  std::vector<double> pressure = reader.observable_scalar("pressure");
  std::vector<std::int64_t> steps = reader.observable_step("pressure");
  std::vector<double> times = reader.observable_time("pressure");
  ASSERT_EQ(pressure.size(), std::size_t(rows));
  ASSERT_EQ(steps.size(), std::size_t(rows));
  ASSERT_EQ(times.size(), std::size_t(rows));
  for (int i = 0; i < rows; ++i) {
    ASSERT_EQ(pressure[i], std::sin(i)) << i;
    ASSERT_EQ(steps[i], i);
    ASSERT_EQ(times[i], 0.5 * i);
  }
  std::vector<Mat2> stress = reader.observable_tensor("stress_static");
  std::vector<std::int64_t> stress_steps = reader.observable_step("stress_static");
  ASSERT_EQ(stress.size(), std::size_t(rows / 2));
  for (int r = 0; r < rows / 2; ++r) {
    ASSERT_EQ(stress[r], tensor(2 * r)) << r;
    ASSERT_EQ(stress_steps[r], 2 * r);
  }
  // Row-major on disk: value[r][0][1] is T_xy.
  RawFile raw(path);
  std::vector<double> flat = raw_read<double>(raw.id, "/observables/stress_static/value", H5T_NATIVE_DOUBLE);
  EXPECT_EQ(flat[4 * 3 + 1], tensor(6)(0, 1));
  EXPECT_EQ(flat[4 * 3 + 2], tensor(6)(1, 0));

  EXPECT_THROW(reader.observable_tensor("pressure"), UsageError);
  EXPECT_THROW(reader.observable_scalar("stress_static"), UsageError);
  EXPECT_THROW(reader.observable_scalar("temperature"), UsageError);
}

TEST_F(IoObservables, RejectMisuse) {
  TrajectoryWriter writer = writer_with_one_frame(file("obs.h5"));
  writer.append_observable("pressure", 5, 0.0, 1.0);
  EXPECT_THROW(writer.append_observable("pressure", 5, 0.0, 1.0), RuntimeFailure);  // step repeats
  EXPECT_THROW(writer.append_observable("pressure", 6, 0.0, tensor(1)), RuntimeFailure);
  EXPECT_THROW(writer.append_observable("a/b", 6, 0.0, 1.0), RuntimeFailure);
  writer.close();
  EXPECT_THROW(writer.append_observable("pressure", 7, 0.0, 1.0), RuntimeFailure);
}

// Speed is measured in bench/bench_io.cpp; here only that a million rows all arrive.
TEST_F(IoObservables, MillionScalarAppendsAllStored) {
  std::string path = file("many.h5");
  const int rows = 1000000;
  {
    TrajectoryWriter writer = writer_with_one_frame(path);
    for (int i = 0; i < rows; ++i) writer.append_observable("pressure", i, 1e-3 * i, 1.0 + 1e-6 * i);
    writer.close();
  }
  auto values = TrajectoryReader(path).observable_scalar("pressure");
  ASSERT_EQ(values.size(), std::size_t(rows));
  EXPECT_EQ(values[rows - 1], 1.0 + 1e-6 * (rows - 1));
  EXPECT_EQ(TrajectoryReader(path).observable_step("pressure")[123456], 123456);
}

// ---- resume ----

// The same run, written uninterrupted or stopped and resumed from a checkpoint.
struct ShearRun {
  static constexpr std::size_t kGrains = 9;
  static constexpr int kFrames = 6, kFrameEvery = 10;
  std::vector<Frame> frames;
  ShearRun() {
    for (int k = 0; k < kFrames; ++k)
      // Contacts appear from frame 2 on, so a resume can land before or after that.
      frames.push_back(make_frame(kGrains, k * kFrameEvery, std::size_t(3 + k), true, 100 + k, k >= 2));
  }
  static void observables(TrajectoryWriter& w, int from_step, int to_step) {
    for (int s = from_step; s <= to_step; ++s) {
      w.append_observable("strain", s, 0.1 * s, 1e-3 * s);
      w.append_observable("stress_collisional", s, 0.1 * s, tensor(s));
    }
  }
  TrajectoryWriter start(const std::string& path) const {
    TrajectoryWriter w(path);
    Parameters p;
    p.set("rate", 0.01);
    w.write_parameters(p);
    w.write_grains(make_grains(kGrains, 7), frames[0].box);
    w.set_lees_edwards_rate(0.01);
    return w;
  }
  // Frames [from, to), each after the observables of the steps leading to it, as a
  // simulation writes them; the last frame is followed by a few more steps.
  void segment(TrajectoryWriter& w, int from, int to) const {
    for (int k = from; k < to; ++k) {
      observables(w, k == 0 ? 0 : (k - 1) * kFrameEvery + 1, k * kFrameEvery);
      w.append_frame(frames[std::size_t(k)]);
    }
    if (to == kFrames) observables(w, (kFrames - 1) * kFrameEvery + 1, (kFrames - 1) * kFrameEvery + 5);
  }
};

TEST_F(IoReopen, ForAppendEqualsUninterruptedRun) {
  ShearRun run;
  std::string whole = file("whole.h5");
  {
    TrajectoryWriter w = run.start(whole);
    run.segment(w, 0, ShearRun::kFrames);
  }
  DatasetContents expected = all_datasets(whole);
  ASSERT_TRUE(expected.contains("/contacts/frame_offset"));

  for (int keep : {0, 1, 3, 5}) {
    SCOPED_TRACE("keep " + std::to_string(keep) + " frames");
    std::string resumed = file("resumed" + std::to_string(keep) + ".h5");
    {
      // The interrupted run got further than its last checkpoint.
      TrajectoryWriter w = run.start(resumed);
      run.segment(w, 0, std::min(keep + 2, ShearRun::kFrames));
      ShearRun::observables(w, 1000, 1004);  // rows after the checkpoint, to be dropped
    }
    {
      std::int64_t checkpoint_step = keep == 0 ? -1 : (keep - 1) * ShearRun::kFrameEvery;
      TrajectoryWriter w = TrajectoryWriter::reopen_for_append(resumed, std::size_t(keep), checkpoint_step);
      EXPECT_EQ(w.frame_count(), std::size_t(keep));
      run.segment(w, keep, ShearRun::kFrames);
    }
    expect_datasets(resumed, expected);
    TrajectoryReader reader(resumed);
    for (std::size_t k = 0; k < reader.frame_count(); ++k) expect_same_frame(reader.frame(k), run.frames[k]);
  }
}

TEST_F(IoReopen, RefusesMissingFrames) {
  ShearRun run;
  std::string path = file("short.h5");
  {
    TrajectoryWriter w = run.start(path);
    run.segment(w, 0, 2);
  }
  try {
    TrajectoryWriter::reopen_for_append(path, 3, 100);
    ADD_FAILURE() << "no UsageError";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

// A process killed between two checkpoints leaves datasets of unequal lengths (HDF5
// flushes the extent of some and not of others), each at least as long as at its last
// checkpoint, and rows past a flushed extent hold fill values where no data reached
// the file. Reopening keeps the checkpoint's rows and continues as if uninterrupted.
TEST_F(IoReopen, ForAppendAcceptsDatasetsLongerThanTheCheckpoint) {
  ShearRun run;
  std::string whole = file("whole.h5");
  {
    TrajectoryWriter w = run.start(whole);
    run.segment(w, 0, ShearRun::kFrames);
  }
  DatasetContents expected = all_datasets(whole);
  const int keep = 3;
  const std::int64_t checkpoint_step = (keep - 1) * ShearRun::kFrameEvery;
  std::string resumed = file("uneven.h5");
  {
    TrajectoryWriter w = run.start(resumed);
    w.mark_unfinished();
    run.segment(w, 0, keep);
    ShearRun::observables(w, int(checkpoint_step) + 1, int(checkpoint_step) + 4);
  }
  auto grow = [&](const std::string& name, hsize_t extra) {
    File f = open_file(resumed, true);
    Dataset d = open_dataset(f.get(), name);
    std::vector<hsize_t> dims = shape(d.get());
    dims[0] += extra;
    ASSERT_GE(H5Dset_extent(d.get(), dims.data()), 0) << name;
  };
  grow("/particles/grains/velocity/value", 1);
  grow("/particles/grains/position/step", 2);
  grow("/contacts/frame_offset", 1);
  grow("/contacts/pair", 5);
  grow("/observables/strain/step", 3);  // steps of 0 after the last step written
  grow("/observables/stress_collisional/value", 7);

  // The resume path reads the partial output as of the checkpoint: its frames only.
  {
    TrajectoryReader partial = TrajectoryReader::partial_output(resumed, keep);
    EXPECT_EQ(partial.frame_count(), std::size_t(keep));
    EXPECT_EQ(partial.frame_steps().size(), std::size_t(keep));
    for (std::size_t k = 0; k < std::size_t(keep); ++k) expect_same_frame(partial.frame(k), run.frames[k]);
  }
  {
    TrajectoryWriter w = TrajectoryWriter::reopen_for_append(resumed, keep, checkpoint_step);
    EXPECT_EQ(w.frame_count(), std::size_t(keep));
    run.segment(w, keep, ShearRun::kFrames);
  }
  expect_datasets(resumed, expected);
}

TEST_F(IoReopen, PartialOutputShorterThanTheCheckpointIsRefused) {
  ShearRun run;
  std::string path = file("short.h5");
  {
    TrajectoryWriter w = run.start(path);
    w.mark_unfinished();
    run.segment(w, 0, 3);
  }
  {
    File f = open_file(path, true);
    Dataset d = open_dataset(f.get(), "/contacts/frame_offset");
    hsize_t rows = 3;  // one fewer than 3 frames need
    ASSERT_GE(H5Dset_extent(d.get(), &rows), 0);
  }
  EXPECT_EQ(TrajectoryReader::partial_output(path, 2).frame_count(), 2u);
  for (std::size_t frames : {3u, 4u}) {
    try {
      TrajectoryReader::partial_output(path, frames);
      ADD_FAILURE() << "no UsageError for " << frames << " frames";
    } catch (const UsageError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  }
}

// ---- the unit of time ----

using IoTimeUnit = IoTest;

// Every time dataset carries a `unit` attribute: "T" (code time) unless the writer was given
// another unit, in which the times are then stored (code time / code_per_unit), also
// after a reopen for append.
TEST_F(IoTimeUnit, EveryTimeDatasetNamesItsUnitAndHoldsTimesInIt) {
  const std::string code = file("code.h5"), tau = file("tau.h5");
  const GrainProperties grains = make_grains(5, 1);
  for (const std::string& path : {code, tau}) {
    TrajectoryWriter w(path);
    if (path == tau) w.set_time_unit({"tau", 0.5});
    w.write_grains(grains, make_frame(5, 0, 0, false, 2).box);
    Frame f = make_frame(5, 4, 2, false, 3);
    f.time = 2.0;
    w.append_frame(f);
    w.append_observable("height", 4, 2.0, 1.0);
  }
  {
    TrajectoryWriter w = TrajectoryWriter::reopen_for_append(tau, 1, 4);
    w.set_time_unit({"tau", 0.5});
    Frame f = make_frame(5, 8, 2, false, 4);
    f.time = 4.0;
    w.append_frame(f);
    w.append_observable("height", 8, 4.0, 1.0);
  }
  const std::vector<std::string> datasets = {
      "/particles/grains/position/time",    "/particles/grains/velocity/time",
      "/particles/grains/orientation/time", "/particles/grains/angular_velocity/time",
      "/particles/grains/box/edges/time",   "/observables/height/time"};
  TrajectoryReader c(code), t(tau);
  for (const std::string& d : datasets) {
    EXPECT_EQ(c.attributes(d).get_string("unit"), "T") << d;
    EXPECT_EQ(t.attributes(d).get_string("unit"), "tau") << d;
  }
  EXPECT_EQ(c.frame_times(), std::vector<double>{2.0});
  EXPECT_EQ(c.observable_time("height"), std::vector<double>{2.0});
  EXPECT_EQ(t.frame_times(), (std::vector<double>{4.0, 8.0}));
  EXPECT_EQ(t.observable_time("height"), (std::vector<double>{4.0, 8.0}));
}

// ---- reproducibility ----

TEST_F(IoDeterminism, IdenticalInputsGiveIdenticalBytes) {
  ShearRun run;
  auto write = [&](const std::string& path) {
    TrajectoryWriter w = run.start(path);
    run.segment(w, 0, ShearRun::kFrames);
  };
  write(file("a.h5"));
  // Object timestamps have a resolution of one second: make sure they would differ.
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));
  write(file("b.h5"));
  std::string a = file_bytes(file("a.h5")), b = file_bytes(file("b.h5"));
  ASSERT_GT(a.size(), 1000u);
  EXPECT_TRUE(a == b) << "files of " << a.size() << " and " << b.size() << " bytes differ";
}

}  // namespace
