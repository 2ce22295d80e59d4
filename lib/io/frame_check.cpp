#include "io/frame_check.hpp"
#include "core/format.hpp"

#include <cmath>
#include <cstdio>

#include "io/schema.hpp"

namespace granflow::io {

namespace {

std::string vector_text(double x, double y) { return "(" + format_number(x, 17) + ", " + format_number(y, 17) + ")"; }

std::string at_frame(std::size_t frame) { return "frame " + std::to_string(frame); }

}  // namespace

std::string grains_problem(const GrainProperties& grains) {
  const std::pair<const char*, const std::vector<double>*> columns[] = {{"radius", &grains.radius},
                                                                        {"mass", &grains.mass}};
  for (const auto& [name, values] : columns)
    for (std::size_t i = 0; i < values->size(); ++i) {
      const double v = (*values)[i];
      if (!(std::isfinite(v) && v > 0))
        return schema::kGrains + "/" + name + ": grain " + std::to_string(i) + " is " + format_number(v, 17) +
               ", must be finite and > 0";
    }
  return "";
}

std::string box_problem(const Box& box, std::size_t frame) {
  const std::string where = schema::kEdges + "/value: " + at_frame(frame) + ": ";
  if (!(std::isfinite(box.lx) && box.lx > 0))
    return where + "box width " + format_number(box.lx, 17) + ", must be finite and > 0";
  if (!(std::isfinite(box.ly) && box.ly > 0))
    return where + "box height " + format_number(box.ly, 17) + ", must be finite and > 0";
  if (!std::isfinite(box.offset))
    return where + "Lees-Edwards offset " + format_number(box.offset, 17) + ", must be finite";
  return "";
}

std::string frame_problem(const Frame& frame, std::size_t k, std::size_t grains, std::int64_t first_row) {
  if (std::string box = box_problem(frame.box, k); !box.empty()) return box;
  auto grain = [&](const std::string& element, std::size_t i, const std::string& value) {
    return element + "/value: " + at_frame(k) + ", grain " + std::to_string(i) + " is " + value + ", must be finite";
  };
  for (std::size_t i = 0; i < frame.position.size(); ++i)
    if (!frame.position[i].allFinite())
      return grain(schema::kPosition, i, vector_text(frame.position[i].x(), frame.position[i].y()));
  for (std::size_t i = 0; i < frame.velocity.size(); ++i)
    if (!frame.velocity[i].allFinite())
      return grain(schema::kVelocity, i, vector_text(frame.velocity[i].x(), frame.velocity[i].y()));
  for (std::size_t i = 0; i < frame.orientation.size(); ++i)
    if (!std::isfinite(frame.orientation[i]))
      return grain(schema::kOrientation, i, format_number(frame.orientation[i], 17));
  for (std::size_t i = 0; i < frame.angular_velocity.size(); ++i)
    if (!std::isfinite(frame.angular_velocity[i]))
      return grain(schema::kAngularVelocity, i, format_number(frame.angular_velocity[i], 17));

  if (!frame.has_contacts) return "";
  const ContactRecords& c = frame.contacts;
  auto contact = [&](const char* column, std::size_t r, const std::string& what) {
    return schema::kContacts + "/" + column + ": " + at_frame(k) + ", contact " + std::to_string(r) + " (row " +
           std::to_string(first_row + std::int64_t(r)) + ") " + what;
  };
  for (std::size_t r = 0; r < c.size(); ++r) {
    const auto [i, j] = c.pair[r];
    if (!(i >= 0 && j >= 0 && std::size_t(i) < grains && std::size_t(j) < grains))
      return contact("pair", r,
                     "joins grains (" + std::to_string(i) + ", " + std::to_string(j) + "), outside 0.." +
                         std::to_string(grains - 1));
    if (!(std::isfinite(c.normal_force[r]) && c.normal_force[r] >= 0))
      return contact("normal_force", r, "is " + format_number(c.normal_force[r], 17) + ", must be finite and >= 0");
    if (!std::isfinite(c.tangential_force[r]))
      return contact("tangential_force", r, "is " + format_number(c.tangential_force[r], 17) + ", must be finite");
    if (!c.branch[r].allFinite())
      return contact("branch", r, "is " + vector_text(c.branch[r].x(), c.branch[r].y()) + ", must be finite");
    if (!(std::isfinite(c.binary_force[r]) && c.binary_force[r] >= 0))
      return contact("binary_force", r, "is " + format_number(c.binary_force[r], 17) + ", must be finite and >= 0");
    const auto& u = c.pre_normal_velocity[r];
    if (!(std::isfinite(u[0]) && std::isfinite(u[1])))
      return contact("pre_normal_velocity", r, "is " + vector_text(u[0], u[1]) + ", must be finite");
  }
  return "";
}

std::string observable_problem(const std::string& name, const std::string& column, const std::vector<double>& values,
                               std::size_t per_row) {
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (std::isfinite(values[k])) continue;
    std::string where = schema::kObservables + "/" + name + "/" + column + ": row " + std::to_string(k / per_row);
    if (per_row == 4) where += ", element [" + std::to_string(k % 4 / 2) + "][" + std::to_string(k % 2) + "]";
    return where + " is " + format_number(values[k], 17) + ", must be finite";
  }
  return "";
}

}  // namespace granflow::io
