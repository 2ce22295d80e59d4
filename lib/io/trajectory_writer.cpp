#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <map>
#include <optional>

#include "core/error.hpp"
#include "core/version.hpp"
#include "io/extendible_dataset.hpp"
#include "io/frame_check.hpp"
#include "io/hdf5_handle.hpp"
#include "io/schema.hpp"
#include "io/trajectory.hpp"
#include "io/units.hpp"

namespace granflow::io {

namespace {

// Observable rows are buffered and written this many at a time.
constexpr std::size_t kObservableBlock = 4096;

// An H5MD time-dependent element: step [n], time [n], value [n]+inner (doubles).
struct Element {
  ExtendibleDataset step, time, value;

  // Each dataset carries the H5MD `unit` attribute (docs/file-format.md, Units): time the
  // unit its values are in, value that of `quantity`, step "1".
  static Element create(hid_t loc, const std::string& path, const std::vector<hsize_t>& inner,
                        const std::string& time_unit, const std::string& quantity) {
    Group group = create_group(loc, path);
    Element e{ExtendibleDataset::create<std::int64_t>(group.get(), "step", {}),
              ExtendibleDataset::create<double>(group.get(), "time", {}),
              ExtendibleDataset::create<double>(group.get(), "value", inner)};
    write_unit(e.step.id(), "1");
    write_unit(e.time.id(), time_unit);
    write_unit(e.value.id(), unit_of(quantity));
    return e;
  }
  static Element open(hid_t loc, const std::string& path) {
    Group group = open_group(loc, path);
    return {ExtendibleDataset::open<std::int64_t>(group.get(), "step"),
            ExtendibleDataset::open<double>(group.get(), "time"),
            ExtendibleDataset::open<double>(group.get(), "value")};
  }
  void append(const std::int64_t* steps, const double* times, const double* values, hsize_t rows) {
    step.append(steps, rows);
    time.append(times, rows);
    value.append(values, rows);
  }
  void resize(hsize_t rows) {
    step.resize(rows);
    time.resize(rows);
    value.resize(rows);
  }
};

struct Observable {
  Element element;
  std::size_t width = 1;  // doubles per row: 1 (scalar) or 4 (2×2 tensor)
  std::optional<std::int64_t> last_step;
  std::vector<std::int64_t> steps;
  std::vector<double> times, values;

  void flush() {
    element.append(steps.data(), times.data(), values.data(), steps.size());
    steps.clear();
    times.clear();
    values.clear();
  }
};

struct Contacts {
  std::vector<ExtendibleDataset> columns;  // in schema::contact_columns() order
  ExtendibleDataset frame_offset;
  std::int64_t rows = 0;
};

// Everything that holds HDF5 objects of the file, so close() can release it all
// before closing the file itself.
struct Content {
  std::size_t grains = 0;  // 0 until write_grains
  bool periodic_y = true;
  std::vector<Element> elements;  // schema::frame_elements() order
  std::optional<std::int64_t> last_frame_step;
  std::optional<Contacts> contacts;
  std::map<std::string, Observable> observables;  // ordered: flushes in a fixed order
};

}  // namespace

struct TrajectoryWriter::Impl {
  std::string path;
  File file;
  Content content;
  bool unfinished = false;  // the file carries the mark
  TimeUnit time_unit;

  // A time of the code (the engine's) in the file's unit.
  double file_time(double code_time) const { return code_time / time_unit.code_per_unit; }

  // The open file; RuntimeFailure after close().
  hid_t id() const {
    if (!file) throw RuntimeFailure("'" + path + "': trajectory writer used after close()");
    return file.get();
  }

  void create_contacts(std::size_t frames_before) {
    Group group = create_group(id(), schema::kContacts);
    Contacts c;
    for (const auto& column : schema::contact_columns()) {
      c.columns.push_back(
          ExtendibleDataset::create(group.get(), column.name, column.file_type, column.mem_type, column.inner));
      write_unit(c.columns.back().id(), unit_of(column.quantity));
    }
    c.frame_offset = ExtendibleDataset::create<std::int64_t>(group.get(), "frame_offset", {});
    write_unit(c.frame_offset.id(), "1");
    // Frames written before contacts were recorded have none.
    std::vector<std::int64_t> zeros(frames_before + 1, 0);
    c.frame_offset.append(zeros.data(), zeros.size());
    content.contacts = std::move(c);
  }

  void flush_observables() {
    for (auto& [name, observable] : content.observables)
      if (!observable.steps.empty()) observable.flush();
  }

  Observable& observable(const std::string& name, std::size_t width, std::int64_t step) {
    auto it = content.observables.find(name);
    if (it == content.observables.end()) {
      if (name.empty() || name.find('/') != std::string::npos || name == ".")
        throw RuntimeFailure("'" + path + "': invalid observable name '" + name + "'");
      if (!exists(id(), schema::kObservables)) create_group(id(), schema::kObservables);
      std::vector<hsize_t> inner = width == 1 ? std::vector<hsize_t>{} : schema::kTensorShape;
      Observable o;
      o.element = Element::create(id(), schema::kObservables + "/" + name, inner, time_unit.name,
                                  schema::observable_quantity(name));
      o.width = width;
      it = content.observables.emplace(name, std::move(o)).first;
    }
    Observable& o = it->second;
    if (o.width != width)
      throw RuntimeFailure("'" + path + "': observable '" + name + "' is a " + (o.width == 1 ? "scalar" : "tensor") +
                           ", cannot append a " + (width == 1 ? "scalar" : "tensor"));
    if (o.last_step && step <= *o.last_step)
      throw RuntimeFailure("'" + path + "': observable '" + name + "': step " + std::to_string(step) + " after step " +
                           std::to_string(*o.last_step));
    o.last_step = step;
    return o;
  }

  // The most the datasets' chunk caches may hold (ExtendibleDataset::unflushed_bytes).
  std::size_t unflushed_bytes() const {
    std::size_t bytes = 0;
    auto add = [&](const ExtendibleDataset& d) { bytes += d.unflushed_bytes(); };
    auto add_element = [&](const Element& e) {
      add(e.step);
      add(e.time);
      add(e.value);
    };
    for (const Element& e : content.elements) add_element(e);
    if (content.contacts) {
      for (const ExtendibleDataset& d : content.contacts->columns) add(d);
      add(content.contacts->frame_offset);
    }
    for (const auto& [name, observable] : content.observables) add_element(observable.element);
    return bytes;
  }

  void flush() {
    flush_observables();
    flush_file(id(), path, unflushed_bytes());
    auto done = [](Element& e) {
      e.step.flushed();
      e.time.flushed();
      e.value.flushed();
    };
    for (Element& e : content.elements) done(e);
    if (content.contacts) {
      for (ExtendibleDataset& d : content.contacts->columns) d.flushed();
      content.contacts->frame_offset.flushed();
    }
    for (auto& [name, observable] : content.observables) done(observable.element);
  }

  void close(bool finished = true) {
    if (!file) return;
    flush_observables();
    if (finished && unfinished) delete_attribute_if_exists(file.get(), schema::kUnfinished);
    flush();
    content = Content{};
    close_file(file, path);
  }

  // No further write reaches the file: its datasets are left open and the file unclosed
  // (the process ends without closing them, see abandon_file).
  void abandon() {
    if (!file) return;
    new Content(std::move(content));  // deliberately never destroyed: closing a dataset writes it
    content = Content{};
    abandon_file(file);
  }

  ~Impl() {
    try {
      close();
    } catch (const std::exception& e) {
      // A destructor must not throw. While an exception unwinds, that one is reported.
      if (std::uncaught_exceptions() == 0) std::fprintf(stderr, "granflow: closing trajectory failed: %s\n", e.what());
    }
  }
};

TrajectoryWriter::TrajectoryWriter(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
TrajectoryWriter::TrajectoryWriter(TrajectoryWriter&&) noexcept = default;
TrajectoryWriter& TrajectoryWriter::operator=(TrajectoryWriter&&) noexcept = default;
TrajectoryWriter::~TrajectoryWriter() = default;

TrajectoryWriter::TrajectoryWriter(const std::string& path, const std::string& author)
    : impl_(std::make_unique<Impl>()) {
  impl_->path = path;
  impl_->file = create_file(path);
  hid_t file = impl_->file.get();
  Group h5md = create_group(file, schema::kH5md);
  write_attribute(h5md.get(), "version", std::vector<std::int32_t>{1, 1});
  Group author_group = create_group(h5md.get(), "author");
  write_attribute(author_group.get(), "name", author);
  Group creator = create_group(h5md.get(), "creator");
  write_attribute(creator.get(), "name", std::string("granflow"));
  write_attribute(creator.get(), "version", granflow::version());
  write_units_module(h5md.get());
}

void TrajectoryWriter::write_parameters(const Parameters& parameters) {
  write_attributes(schema::kParameters, parameters);
}

void TrajectoryWriter::write_attributes(const std::string& group_path, const Parameters& values) {
  hid_t file = impl_->id();
  Group group = exists(file, group_path) ? open_group(file, group_path) : create_group(file, group_path);
  // name captured explicitly: Clang before 16 cannot capture a structured binding.
  for (const auto& [name, value] : values.items())
    std::visit([&, &name = name](const auto& v) { write_attribute(group.get(), name, v); }, value);
}

void TrajectoryWriter::write_grains(const GrainProperties& grains, const Box& box) {
  hid_t file = impl_->id();
  Content& c = impl_->content;
  const std::string& path = impl_->path;
  if (c.grains != 0) throw RuntimeFailure("'" + path + "': grains written twice");
  std::size_t n = grains.radius.size();
  if (n == 0) throw RuntimeFailure("'" + path + "': a trajectory needs at least one grain");
  if (grains.mass.size() != n || grains.fixed.size() != n)
    throw RuntimeFailure("'" + path + "': grain properties of different sizes (radius " + std::to_string(n) +
                         ", mass " + std::to_string(grains.mass.size()) + ", fixed " +
                         std::to_string(grains.fixed.size()) + ")");

  if (std::string problem = grains_problem(grains); !problem.empty())
    throw RuntimeFailure("'" + path + "': refusing to write " + problem);

  create_group(file, schema::kParticles);
  Group group = create_group(file, schema::kGrains);
  write_dataset(group.get(), "radius", {n}, grains.radius.data());
  write_dataset(group.get(), "mass", {n}, grains.mass.data());
  write_dataset(group.get(), "fixed", {n}, grains.fixed.data());
  for (const auto& [name, quantity] : {std::pair{"radius", "length"}, {"mass", "mass"}, {"fixed", "1"}}) {
    Dataset d = open_dataset(group.get(), name);
    write_unit(d.get(), unit_of(quantity));
  }
  Group box_group = create_group(file, schema::kBox);
  write_attribute(box_group.get(), "dimension", std::int32_t{2});
  write_attribute(box_group.get(), "boundary",
                  std::vector<std::string>{"periodic", box.periodic_y ? "periodic" : "none"});
  if (box.periodic_y) {
    Group lees_edwards = create_group(file, schema::kLeesEdwards);
    write_attribute(lees_edwards.get(), "rate", 0.0);
  }
  for (const auto& element : schema::frame_elements(n, box.periodic_y))
    c.elements.push_back(Element::create(file, element.path, element.inner, impl_->time_unit.name, element.quantity));
  c.grains = n;
  c.periodic_y = box.periodic_y;
}

void TrajectoryWriter::set_time_unit(const TimeUnit& unit) {
  impl_->id();
  const Content& c = impl_->content;
  if (!(unit.code_per_unit > 0) || !std::isfinite(unit.code_per_unit) || unit.name.empty())
    throw RuntimeFailure("'" + impl_->path + "': bad time unit '" + unit.name + "'");
  // A reopened file keeps the unit its time datasets name; a new one takes it before
  // any of them exists.
  if (!c.elements.empty() || !c.observables.empty()) {
    const Element& e = !c.elements.empty() ? c.elements.front() : c.observables.begin()->second.element;
    const std::string stored = has_attribute(e.time.id(), "unit")
                                   ? read_string_attribute(open_attribute(e.time.id(), "unit").get())
                                   : std::string(kCodeTime);
    if (stored != unit.name)
      throw UsageError("'" + impl_->path + "' stores time in unit '" + stored + "', not '" + unit.name + "'");
  }
  impl_->time_unit = unit;
}

double TrajectoryWriter::file_time(double code_time) const { return impl_->file_time(code_time); }

void TrajectoryWriter::set_lees_edwards_rate(double rate) {
  hid_t file = impl_->id();
  const Content& c = impl_->content;
  if (c.grains == 0 || !c.periodic_y)
    throw RuntimeFailure("'" + impl_->path + "': a Lees–Edwards rate needs write_grains() with a box periodic in y");
  Group group = open_group(file, schema::kLeesEdwards);
  write_attribute(group.get(), "rate", rate);
}

void TrajectoryWriter::append_frame(const Frame& frame) {
  impl_->id();
  Content& c = impl_->content;
  const std::string& path = impl_->path;
  if (c.grains == 0) throw RuntimeFailure("'" + path + "': append_frame() before write_grains()");
  auto require_size = [&](const char* what, std::size_t size, std::size_t expected) {
    if (size != expected)
      throw RuntimeFailure("'" + path + "': frame at step " + std::to_string(frame.step) + ": " + what + " has " +
                           std::to_string(size) + " entries, expected " + std::to_string(expected));
  };
  require_size("position", frame.position.size(), c.grains);
  require_size("velocity", frame.velocity.size(), c.grains);
  require_size("orientation", frame.orientation.size(), c.grains);
  require_size("angular_velocity", frame.angular_velocity.size(), c.grains);
  if (frame.box.periodic_y != c.periodic_y)
    throw RuntimeFailure("'" + path + "': frame box boundary differs from write_grains()");
  if (c.last_frame_step && frame.step <= *c.last_frame_step)
    throw RuntimeFailure("'" + path + "': frame step " + std::to_string(frame.step) + " after step " +
                         std::to_string(*c.last_frame_step));
  const ContactRecords& contacts = frame.contacts;
  if (frame.has_contacts) {
    for (const auto& column : schema::contact_columns())
      require_size(("contacts " + column.name).c_str(), column.size(contacts), contacts.size());
    for (const auto& p : contacts.pair)
      if (p[0] < 0 || p[1] < 0 || std::size_t(p[0]) >= c.grains || std::size_t(p[1]) >= c.grains)
        throw RuntimeFailure("'" + path + "': contact pair (" + std::to_string(p[0]) + ", " + std::to_string(p[1]) +
                             ") outside the grains");
  }

  std::size_t frames_before = c.elements.front().value.rows();
  if (std::string problem = frame_problem(frame, frames_before, c.grains, c.contacts ? c.contacts->rows : 0);
      !problem.empty())
    throw RuntimeFailure("'" + path + "': refusing to write " + problem);
  const double edges[4] = {frame.box.lx, 0.0, frame.box.offset, frame.box.ly};
  // One frame of each element, in schema::frame_elements() order.
  const double* values[] = {frame.position.data()->data(),
                            frame.velocity.data()->data(),
                            frame.orientation.data(),
                            frame.angular_velocity.data(),
                            edges,
                            &frame.box.offset};
  const double time = impl_->file_time(frame.time);
  for (std::size_t i = 0; i < c.elements.size(); ++i) c.elements[i].append(&frame.step, &time, values[i], 1);

  if (frame.has_contacts && !c.contacts) impl_->create_contacts(frames_before);
  if (c.contacts) {
    std::size_t rows = frame.has_contacts ? contacts.size() : 0;
    const auto& columns = schema::contact_columns();
    for (std::size_t i = 0; i < columns.size(); ++i) c.contacts->columns[i].append(columns[i].data(contacts), rows);
    c.contacts->rows += std::int64_t(rows);
    c.contacts->frame_offset.append(&c.contacts->rows, 1);
  }
  c.last_frame_step = frame.step;
}

void TrajectoryWriter::append_observable(const std::string& name, std::int64_t step, double time, double value) {
  Observable& o = impl_->observable(name, 1, step);
  o.steps.push_back(step);
  o.times.push_back(impl_->file_time(time));
  o.values.push_back(value);
  if (o.steps.size() >= kObservableBlock) o.flush();
}

void TrajectoryWriter::append_observable(const std::string& name, std::int64_t step, double time, const Mat2& value) {
  Observable& o = impl_->observable(name, 4, step);
  o.steps.push_back(step);
  o.times.push_back(impl_->file_time(time));
  // Row-major [i][j] = T_ij; Eigen stores column-major.
  o.values.insert(o.values.end(), {value(0, 0), value(0, 1), value(1, 0), value(1, 1)});
  if (o.steps.size() >= kObservableBlock) o.flush();
}

void TrajectoryWriter::write_array(const std::string& path, const std::vector<std::size_t>& dims,
                                   const std::vector<double>& values, const Parameters& attributes) {
  hid_t file = impl_->id();
  std::size_t count = 1;
  for (std::size_t d : dims) count *= d;
  if (path.empty() || path.front() != '/' || path.back() == '/' || count != values.size())
    throw RuntimeFailure("'" + impl_->path + "': cannot write array '" + path + "' of shape " +
                         shape_text({dims.begin(), dims.end()}) + " from " + std::to_string(values.size()) + " values");
  // Parent groups, one level at a time (HDF5 does not create intermediate groups by default).
  for (std::size_t slash = path.find('/', 1); slash != std::string::npos; slash = path.find('/', slash + 1)) {
    const std::string parent = path.substr(0, slash);
    if (!exists(file, parent)) create_group(file, parent);
  }
  write_dataset(file, path, {dims.begin(), dims.end()}, values.data());
  Dataset dataset = open_dataset(file, path);
  for (const auto& [name, value] : attributes.items())
    std::visit([&, &name = name](const auto& v) { write_attribute(dataset.get(), name, v); }, value);
  // Arrays described in words (`units`, as gf-incline's /profiles) get their H5MD unit.
  if (attributes.has("units")) write_unit(dataset.get(), unit_of(attributes.get_string("units")));
}

void TrajectoryWriter::flush() { impl_->flush(); }

void TrajectoryWriter::close() { impl_->close(); }
void TrajectoryWriter::close_unfinished() { impl_->close(false); }
void TrajectoryWriter::abandon() { impl_->abandon(); }

void TrajectoryWriter::mark_unfinished() {
  write_attribute(impl_->id(), schema::kUnfinished, std::int64_t(1));
  impl_->unfinished = true;
}

std::size_t TrajectoryWriter::frame_count() const {
  const Content& c = impl_->content;
  return c.elements.empty() ? 0 : c.elements.front().value.rows();
}

const std::string& TrajectoryWriter::path() const { return impl_->path; }

TrajectoryWriter TrajectoryWriter::reopen_for_append(const std::string& path, std::size_t keep_frames,
                                                     std::int64_t keep_observables_through_step) {
  // The same checks and messages as any input; datasets may be longer than keep_frames
  // frames (rows written after the checkpoint by a killed process), never shorter.
  TrajectoryReader::partial_output(path, keep_frames);
  auto impl = std::make_unique<Impl>();
  impl->path = path;
  try {
    impl->file = open_file(path, true);
    hid_t file = impl->file.get();
    impl->unfinished = has_attribute(file, schema::kUnfinished);
    Content& c = impl->content;
    Dataset radius = open_dataset(file, schema::kGrains + "/radius");
    c.grains = shape(radius.get()).at(0);
    c.periodic_y = schema::read_periodic_y(file);
    for (const auto& element : schema::frame_elements(c.grains, c.periodic_y)) {
      c.elements.push_back(Element::open(file, element.path));
      c.elements.back().resize(keep_frames);
    }
    if (keep_frames > 0)
      c.last_frame_step = read_rows<std::int64_t>(c.elements.front().step.id(), keep_frames - 1, 1)[0];

    if (exists(file, schema::kContacts)) {
      Group group = open_group(file, schema::kContacts);
      Contacts contacts;
      for (const auto& column : schema::contact_columns())
        contacts.columns.push_back(ExtendibleDataset::open(group.get(), column.name, column.mem_type));
      contacts.frame_offset = ExtendibleDataset::open<std::int64_t>(group.get(), "frame_offset");
      contacts.rows = read_rows<std::int64_t>(contacts.frame_offset.id(), keep_frames, 1)[0];
      contacts.frame_offset.resize(keep_frames + 1);
      for (auto& column : contacts.columns) column.resize(hsize_t(contacts.rows));
      c.contacts = std::move(contacts);
    }

    if (exists(file, schema::kObservables)) {
      Group group = open_group(file, schema::kObservables);
      for (const std::string& name : link_names(group.get())) {
        Observable o;
        o.element = Element::open(group.get(), name);
        const auto& inner = o.element.value.inner();
        if (!inner.empty() && inner != schema::kTensorShape)
          throw UsageError("'" + path + "': observable '" + name + "' has rows of shape " + shape_text(inner) +
                           ", expected scalars or [2][2]");
        o.width = inner.empty() ? 1 : 4;
        // Rows through the checkpoint's step; after them, rows written since or, past
        // the data that reached the file, fill values (step 0, not increasing).
        std::vector<std::int64_t> steps = read_all<std::int64_t>(o.element.step.id());
        std::size_t kept = 0;
        while (kept < steps.size() && steps[kept] <= keep_observables_through_step &&
               (kept == 0 || steps[kept] > steps[kept - 1]))
          ++kept;
        if (kept > o.element.time.rows() || kept > o.element.value.rows())
          throw UsageError("'" + path + "': observable '" + name + "' has fewer time or value rows than the " +
                           std::to_string(kept) + " steps it keeps");
        o.element.resize(hsize_t(kept));
        if (kept > 0) o.last_step = steps[kept - 1];
        c.observables.emplace(name, std::move(o));
      }
    }
  } catch (const Hdf5Error& e) {
    throw UsageError(e.what());
  }
  return TrajectoryWriter(std::move(impl));
}

}  // namespace granflow::io
