#include "io/schema.hpp"

#include <map>

#include "core/error.hpp"

namespace granflow::io::schema {

std::vector<FrameElement> frame_elements(hsize_t grains, bool periodic_y) {
  std::vector<FrameElement> elements{
      {kPosition, {grains, 2}, "[grains][2]", "length"},
      {kVelocity, {grains, 2}, "[grains][2]", "velocity"},
      {kOrientation, {grains}, "[grains]", "radian"},
      {kAngularVelocity, {grains}, "[grains]", "radian/time"},
      {kEdges, {2, 2}, "[2][2]", "length"},
  };
  if (periodic_y) elements.push_back({kOffset, {}, "", "length"});
  return elements;
}

namespace {

// Storage of one contact column as raw bytes: every column is a std::vector.
template <auto Member>
ContactColumn column(const std::string& name, hid_t file_type, hid_t mem_type, std::vector<hsize_t> inner,
                     const std::string& quantity) {
  return {name,
          file_type,
          mem_type,
          std::move(inner),
          [](const ContactRecords& c) { return (c.*Member).size(); },
          [](const ContactRecords& c) -> const void* { return (c.*Member).data(); },
          [](ContactRecords& c, std::size_t rows) -> void* {
            (c.*Member).resize(rows);
            return (c.*Member).data();
          },
          quantity};
}

}  // namespace

const std::vector<ContactColumn>& contact_columns() {
  // Rows of pairs, branches and velocity pairs are two contiguous values in memory.
  static_assert(sizeof(std::array<std::int32_t, 2>) == 2 * sizeof(std::int32_t));
  static_assert(sizeof(std::array<double, 2>) == 2 * sizeof(double));
  static_assert(sizeof(Vec2) == 2 * sizeof(double));
  static const std::vector<ContactColumn> columns{
      column<&ContactRecords::pair>("pair", H5T_STD_I32LE, H5T_NATIVE_INT32, {2}, "1"),
      column<&ContactRecords::normal_force>("normal_force", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {}, "force"),
      column<&ContactRecords::tangential_force>("tangential_force", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {}, "force"),
      column<&ContactRecords::branch>("branch", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {2}, "length"),
      column<&ContactRecords::binary_force>("binary_force", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {}, "force"),
      column<&ContactRecords::pre_normal_velocity>("pre_normal_velocity", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {2},
                                                   "velocity"),
      column<&ContactRecords::age>("age", H5T_STD_I64LE, H5T_NATIVE_INT64, {}, "1"),
  };
  return columns;
}

const std::string& observable_quantity(const std::string& name) {
  static const std::map<std::string, std::string> quantities{
      {"strain", "1"},
      {"pressure", "force/length"},
      {"shear_stress", "force/length"},
      {"normal_stress_difference", "1"},
      {"temperature", "velocity²"},
      {"stress_kinetic", "force/length"},
      {"stress_static", "force/length"},
      {"stress_collisional", "force/length"},
      {"flow_rate", "velocity"},
      {"kinetic_energy", "mass·velocity²"},
      {"height", "length"},
      {"contacts", "1"},
      {"solver_iterations", "1"},
      {"solver_residual", "length"},
      {"max_overlap", "length"},
      {"unconverged_steps", "1"},
      {"unconverged_residual", "length"},
      {"collisions", "1"},
      {"collision_velocity_product", "velocity²"},
      {"dissipated_energy", "mass·velocity²"},
      {"packing_fraction", "1"},
      {"minimiser_iterations", "1"},
  };
  const auto it = quantities.find(name);
  if (it == quantities.end()) throw RuntimeFailure("observable '" + name + "' has no unit (io/schema.cpp)");
  return it->second;
}

bool read_periodic_y(hid_t file) {
  Group box = open_group(file, kBox);
  Attribute dimension = open_attribute(box.get(), "dimension");
  if (read_int_attribute(dimension.get()) != 2) throw Hdf5Error(where(box.get()) + ": attribute dimension must be 2");
  Attribute boundary_attribute = open_attribute(box.get(), "boundary");
  std::vector<std::string> boundary = read_string_attributes(boundary_attribute.get());
  if (boundary.size() != 2 || boundary[0] != "periodic" || (boundary[1] != "periodic" && boundary[1] != "none"))
    throw Hdf5Error(where(box.get()) +
                    ": attribute boundary must be [\"periodic\", \"periodic\"] or "
                    "[\"periodic\", \"none\"]");
  return boundary[1] == "periodic";
}

}  // namespace granflow::io::schema
