#include <algorithm>
#include <filesystem>
#include <optional>

#include "core/error.hpp"
#include "core/output_file.hpp"
#include "io/frame_check.hpp"
#include "io/hdf5_handle.hpp"
#include "io/schema.hpp"
#include "io/trajectory.hpp"

namespace granflow::io {

namespace {

// Any HDF5 failure while reading means the input file is bad: exit code 2.
template <class F>
auto as_usage_error(F&& body) -> decltype(body()) {
  try {
    return body();
  } catch (const Hdf5Error& e) {
    throw UsageError(e.what());
  }
}

}  // namespace

struct TrajectoryReader::Impl {
  std::string path;
  File file;
  std::size_t frames = 0, grains = 0;
  bool periodic_y = true;
  bool contacts = false;
  // Set for a partial output read as of a checkpoint: its frame count, and datasets
  // may be longer than the rows it needs.
  std::optional<std::size_t> as_of_frames;

  [[noreturn]] void bad(const std::string& what) const { throw UsageError("'" + path + "': " + what); }

  void require_group(const std::string& group, const char* kind) const {
    if (!exists(file.get(), group)) bad(std::string(kind) + ": no group " + group);
  }

  // Opens a dataset and checks its shape; inner is everything after the first dimension.
  Dataset checked(const std::string& name, hsize_t rows, const std::vector<hsize_t>& inner,
                  const std::string& expected) const {
    if (!exists(file.get(), name)) bad("missing dataset " + name);
    Dataset dataset = open_dataset(file.get(), name);
    std::vector<hsize_t> dims = shape(dataset.get()), want{rows};
    want.insert(want.end(), inner.begin(), inner.end());
    const bool longer_is_fine = as_of_frames && dims.size() == want.size() && dims[0] >= want[0] &&
                                std::equal(dims.begin() + 1, dims.end(), want.begin() + 1);
    if (dims != want && !longer_is_fine)
      bad(name + " has shape " + shape_text(dims) + " but must be " + expected + " = " + shape_text(want));
    return dataset;
  }

  void validate() {
    require_group(schema::kH5md, "not an H5MD file");
    require_group(schema::kGrains, "not a granflow trajectory");
    const std::string position = schema::kPosition + "/value";
    if (!exists(file.get(), position)) bad("missing dataset " + position);
    Dataset dataset = open_dataset(file.get(), position);
    std::vector<hsize_t> dims = shape(dataset.get());
    if (dims.size() != 3 || dims[2] != 2)
      bad(position + " has shape " + shape_text(dims) + " but must be [frames][grains][2]");
    frames = dims[0];
    grains = dims[1];
    if (as_of_frames) {
      if (frames < *as_of_frames)
        bad("has " + std::to_string(frames) + " frame(s), fewer than the " + std::to_string(*as_of_frames) +
            " its checkpoint counts");
      frames = *as_of_frames;
    }

    for (const char* name : {"radius", "mass", "fixed"}) checked(schema::kGrains + "/" + name, grains, {}, "[grains]");
    require_group(schema::kBox, "not a granflow trajectory");
    periodic_y = schema::read_periodic_y(file.get());
    for (const auto& element : schema::frame_elements(grains, periodic_y)) {
      checked(element.path + "/step", frames, {}, "[frames]");
      checked(element.path + "/time", frames, {}, "[frames]");
      checked(element.path + "/value", frames, element.inner, "[frames]" + element.inner_text);
    }

    contacts = exists(file.get(), schema::kContacts);
    if (contacts) {
      Dataset offsets = checked(schema::kFrameOffset, frames + 1, {}, "[frames+1]");
      std::vector<std::int64_t> offset = read_rows<std::int64_t>(offsets.get(), 0, frames + 1);
      for (std::size_t k = 0; k < frames; ++k)
        if (offset[k + 1] < offset[k]) bad(schema::kFrameOffset + " decreases at frame " + std::to_string(k));
      if (offset[0] != 0) bad(schema::kFrameOffset + " must start at 0");
      for (const auto& column : schema::contact_columns())
        checked(schema::kContacts + "/" + column.name, hsize_t(offset[frames]), column.inner,
                "[contacts]" + (column.inner.empty() ? "" : shape_text(column.inner)));
    }
  }

  std::int64_t frame_rows(std::size_t k) const {
    Dataset offsets = open_dataset(file.get(), schema::kFrameOffset);
    return read_rows<std::int64_t>(offsets.get(), k, 1)[0];
  }

  void require_frame(std::size_t k) const {
    if (k >= frames)
      bad("frame " + std::to_string(k) + " out of range: the file has " + std::to_string(frames) + " frames");
  }

  Box box(std::size_t k) const {
    require_frame(k);
    Dataset edges = open_dataset(file.get(), schema::kEdges + "/value");
    std::vector<double> e = read_rows<double>(edges.get(), k, 1);  // [[lx, 0], [offset, ly]]
    Box b;
    b.lx = e[0];
    b.offset = e[2];
    b.ly = e[3];
    b.periodic_y = periodic_y;
    if (std::string problem = box_problem(b, k); !problem.empty()) bad(problem);
    return b;
  }

  template <class T>
  std::vector<T> read(const std::string& name) const {
    Dataset dataset = open_dataset(file.get(), name);
    return read_all<T>(dataset.get());
  }

  // The first `frames` rows of a per-frame dataset.
  template <class T>
  std::vector<T> read_frames(const std::string& name) const {
    Dataset dataset = open_dataset(file.get(), name);
    return read_rows<T>(dataset.get(), 0, frames);
  }

  // The observable's value dataset, checked to hold rows of the given shape.
  Dataset observable_value(const std::string& name, const std::vector<hsize_t>& inner) const {
    if (!has_observable(name)) bad("no observable '" + name + "'");
    Dataset value = open_dataset(file.get(), schema::kObservables + "/" + name + "/value");
    std::vector<hsize_t> dims = shape(value.get());
    if (dims.empty() || std::vector<hsize_t>(dims.begin() + 1, dims.end()) != inner)
      bad("observable '" + name + "' has shape " + shape_text(dims) + ", expected [rows]" +
          (inner.empty() ? " (a scalar)" : shape_text(inner) + " (a tensor)"));
    return value;
  }

  bool has_observable(const std::string& name) const {
    return name.find('/') == std::string::npos && !name.empty() &&
           exists(file.get(), schema::kObservables + "/" + name + "/value");
  }
};

TrajectoryReader::TrajectoryReader(TrajectoryReader&&) noexcept = default;
TrajectoryReader& TrajectoryReader::operator=(TrajectoryReader&&) noexcept = default;
TrajectoryReader::~TrajectoryReader() = default;

TrajectoryReader TrajectoryReader::partial_output(const std::string& path, std::size_t frames) {
  return TrajectoryReader(path, true, frames);
}

TrajectoryReader::TrajectoryReader(const std::string& path, bool accept_unfinished)
    : TrajectoryReader(path, accept_unfinished, std::nullopt) {}

TrajectoryReader::TrajectoryReader(const std::string& path, bool accept_unfinished,
                                   std::optional<std::size_t> as_of_frames)
    : impl_(std::make_unique<Impl>()) {
  impl_->path = path;
  impl_->as_of_frames = as_of_frames;
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) impl_->bad("no such file");
  if (std::filesystem::is_directory(path, ec)) impl_->bad("is a directory, not a trajectory file");
  require_regular_file(path);
  silence_hdf5_errors();
#if H5_VERSION_GE(1, 12, 0)
  htri_t is_hdf5 = H5Fis_accessible(path.c_str(), H5P_DEFAULT);
#else
  htri_t is_hdf5 = H5Fis_hdf5(path.c_str());
#endif
  if (is_hdf5 < 0) impl_->bad("cannot read: " + hdf5_reason());
  if (is_hdf5 == 0) impl_->bad("not an HDF5 file");
  as_usage_error([&] {
    impl_->file = open_file(path, false);
    if (!accept_unfinished && has_attribute(impl_->file.get(), schema::kUnfinished))
      throw UsageError(unfinished_run_message(path));
    impl_->validate();
  });
}

std::size_t TrajectoryReader::frame_count() const { return impl_->frames; }
std::size_t TrajectoryReader::grain_count() const { return impl_->grains; }
bool TrajectoryReader::has_contacts() const { return impl_->contacts; }
const std::string& TrajectoryReader::path() const { return impl_->path; }

GrainProperties TrajectoryReader::grains() const {
  return as_usage_error([&] {
    GrainProperties g;
    g.radius = impl_->read<double>(schema::kGrains + "/radius");
    g.mass = impl_->read<double>(schema::kGrains + "/mass");
    g.fixed = impl_->read<std::uint8_t>(schema::kGrains + "/fixed");
    if (std::string problem = grains_problem(g); !problem.empty()) impl_->bad(problem);
    return g;
  });
}

Box TrajectoryReader::box(std::size_t frame) const {
  return as_usage_error([&] { return impl_->box(frame); });
}

Frame TrajectoryReader::frame(std::size_t k) const {
  impl_->require_frame(k);
  return as_usage_error([&] {
    hid_t file = impl_->file.get();
    Frame f;
    f.box = impl_->box(k);
    Dataset step = open_dataset(file, schema::kPosition + "/step");
    Dataset time = open_dataset(file, schema::kPosition + "/time");
    f.step = read_rows<std::int64_t>(step.get(), k, 1)[0];
    f.time = read_rows<double>(time.get(), k, 1)[0];
    std::size_t n = impl_->grains;
    auto read_frame = [&](const std::string& element, double* out) {
      Dataset value = open_dataset(file, element + "/value");
      read_rows(value.get(), k, 1, H5T_NATIVE_DOUBLE, out);
    };
    f.position.resize(n);
    f.velocity.resize(n);
    f.orientation.resize(n);
    f.angular_velocity.resize(n);
    read_frame(schema::kPosition, f.position.data()->data());
    read_frame(schema::kVelocity, f.velocity.data()->data());
    read_frame(schema::kOrientation, f.orientation.data());
    read_frame(schema::kAngularVelocity, f.angular_velocity.data());

    f.has_contacts = impl_->contacts;
    std::int64_t first = 0;
    if (f.has_contacts) {
      first = impl_->frame_rows(k);
      const std::int64_t rows = impl_->frame_rows(k + 1) - first;
      for (const auto& column : schema::contact_columns()) {
        Dataset dataset = open_dataset(file, schema::kContacts + "/" + column.name);
        read_rows(dataset.get(), hsize_t(first), hsize_t(rows), column.mem_type,
                  column.resize(f.contacts, std::size_t(rows)));
      }
    }
    if (std::string problem = frame_problem(f, k, n, first); !problem.empty()) impl_->bad(problem);
    return f;
  });
}

std::vector<std::int64_t> TrajectoryReader::frame_steps() const {
  return as_usage_error([&] { return impl_->read_frames<std::int64_t>(schema::kPosition + "/step"); });
}

std::vector<double> TrajectoryReader::frame_times() const {
  return as_usage_error([&] { return impl_->read_frames<double>(schema::kPosition + "/time"); });
}

std::size_t TrajectoryReader::frame_index(long long k, const std::string& option) const {
  const long long frames = (long long)frame_count();
  const long long index = k < 0 ? k + frames : k;
  if (index < 0 || index >= frames)
    throw UsageError("'" + impl_->path + "' has " + std::to_string(frames) + " frame(s); " + option + " " +
                     std::to_string(k) + " is out of range");
  return std::size_t(index);
}

Parameters TrajectoryReader::parameters() const { return attributes(schema::kParameters); }

Parameters TrajectoryReader::attributes(const std::string& group_path) const {
  return as_usage_error([&] {
    Parameters p(impl_->path);
    hid_t file = impl_->file.get();
    if (!exists(file, group_path)) return p;
    // A group or a dataset (e.g. the `unit` of a time dataset).
    const Handle<H5Oclose> object(check(H5Oopen(file, group_path.c_str(), H5P_DEFAULT), file, "open " + group_path));
    for (const std::string& name : attribute_names(object.get())) {
      Attribute attribute = open_attribute(object.get(), name);
      switch (attribute_class(attribute.get())) {
        case H5T_FLOAT: p.set(name, read_double_attribute(attribute.get())); break;
        case H5T_INTEGER: p.set(name, read_int_attribute(attribute.get())); break;
        case H5T_STRING: p.set(name, read_string_attribute(attribute.get())); break;
        default: impl_->bad("parameter '" + name + "' is not a number or a string");
      }
    }
    return p;
  });
}

double TrajectoryReader::lees_edwards_rate() const {
  return as_usage_error([&] {
    hid_t file = impl_->file.get();
    if (!exists(file, schema::kLeesEdwards)) return 0.0;
    Group group = open_group(file, schema::kLeesEdwards);
    if (!has_attribute(group.get(), "rate")) return 0.0;
    Attribute rate = open_attribute(group.get(), "rate");
    return read_double_attribute(rate.get());
  });
}

bool TrajectoryReader::has_observable(const std::string& name) const {
  return as_usage_error([&] { return impl_->has_observable(name); });
}

std::vector<std::string> TrajectoryReader::observable_names() const {
  return as_usage_error([&] {
    hid_t file = impl_->file.get();
    if (!exists(file, schema::kObservables)) return std::vector<std::string>{};
    Group group = open_group(file, schema::kObservables);
    return link_names(group.get());
  });
}

std::vector<std::int64_t> TrajectoryReader::observable_step(const std::string& name) const {
  return as_usage_error([&] {
    if (!impl_->has_observable(name)) impl_->bad("no observable '" + name + "'");
    return impl_->read<std::int64_t>(schema::kObservables + "/" + name + "/step");
  });
}

std::vector<double> TrajectoryReader::observable_time(const std::string& name) const {
  return as_usage_error([&] {
    if (!impl_->has_observable(name)) impl_->bad("no observable '" + name + "'");
    std::vector<double> time = impl_->read<double>(schema::kObservables + "/" + name + "/time");
    if (std::string problem = observable_problem(name, "time", time); !problem.empty()) impl_->bad(problem);
    return time;
  });
}

std::vector<double> TrajectoryReader::observable_scalar(const std::string& name) const {
  return as_usage_error([&] {
    Dataset value = impl_->observable_value(name, {});
    std::vector<double> values = read_all<double>(value.get());
    if (std::string problem = observable_problem(name, "value", values); !problem.empty()) impl_->bad(problem);
    return values;
  });
}

std::vector<Mat2> TrajectoryReader::observable_tensor(const std::string& name) const {
  return as_usage_error([&] {
    Dataset value = impl_->observable_value(name, schema::kTensorShape);
    std::vector<double> flat = read_all<double>(value.get());
    if (std::string problem = observable_problem(name, "value", flat, 4); !problem.empty()) impl_->bad(problem);
    std::vector<Mat2> tensors(flat.size() / 4);
    for (std::size_t r = 0; r < tensors.size(); ++r)
      tensors[r] << flat[4 * r], flat[4 * r + 1], flat[4 * r + 2], flat[4 * r + 3];  // row-major
    return tensors;
  });
}

std::vector<double> TrajectoryReader::array(const std::string& path, std::vector<std::size_t>* dims) const {
  return as_usage_error([&] {
    if (!exists(impl_->file.get(), path)) impl_->bad("missing dataset " + path);
    Dataset dataset = open_dataset(impl_->file.get(), path);
    const std::vector<hsize_t> extent = shape(dataset.get());
    if (dims) dims->assign(extent.begin(), extent.end());
    return read_all<double>(dataset.get());
  });
}

}  // namespace granflow::io
