#include "io/xdmf.hpp"

#include <cstdint>
#include <cstdio>
#include <sstream>
#include <vector>

#include "core/error.hpp"
#include "core/signals.hpp"
#include "io/schema.hpp"

namespace granflow::io {

namespace {

// docs/file-format.md, Grains, Box and Contacts: the datasets referenced, with their types.
struct Source {
  std::string path;
  std::vector<std::size_t> dims;
  const char* type;  // XDMF NumberType and Precision
};
const char* const kDouble = R"(NumberType="Float" Precision="8")";
const char* const kInt32 = R"(NumberType="Int" Precision="4")";
const char* const kInt64 = R"(NumberType="Int" Precision="8")";
const char* const kUint8 = R"(NumberType="UChar" Precision="1")";

std::string join(const std::vector<std::size_t>& values) {
  std::string text;
  for (std::size_t v : values) text += (text.empty() ? "" : " ") + std::to_string(v);
  return text;
}

std::string escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

class Writer {
 public:
  Writer(std::string h5_name) : h5_(escape(h5_name)) {}

  // A whole dataset.
  std::string whole(const Source& s) const {
    return "<DataItem Dimensions=\"" + join(s.dims) + "\" " + s.type + " Format=\"HDF\">" + h5_ + ":" + s.path +
           "</DataItem>";
  }
  // The block start … start+count−1 of a dataset, read by HDF5 itself (only that block
  // leaves the disk), as an item of `shape` (the block's elements, e.g. [N][2]).
  std::string slab(const Source& s, const std::vector<std::size_t>& start, const std::vector<std::size_t>& count,
                   const std::vector<std::size_t>& shape) const {
    const std::vector<std::size_t> stride(start.size(), 1);
    return "<DataItem ItemType=\"HyperSlab\" Dimensions=\"" + join(shape) + "\" " + s.type +
           "><DataItem Dimensions=\"3 " + std::to_string(start.size()) + "\" Format=\"XML\">" + join(start) + " " +
           join(stride) + " " + join(count) + "</DataItem>" + whole(s) + "</DataItem>";
  }

 private:
  std::string h5_;
};

std::string inline_item(const std::string& dims, const char* type, const std::string& values) {
  return "<DataItem Dimensions=\"" + dims + "\" " + type + " Format=\"XML\">" + values + "</DataItem>";
}

// The constant connectivity of one cell (e.g. 0 1 2 3 0): given inline but passed through a Function, since
// ParaView's reader rejects (with an error message, then reads on) inline connectivity beside a
// computed geometry when it tries to cache the grid.
std::string connectivity(std::size_t nodes, const std::string& values) {
  return "<DataItem ItemType=\"Function\" Function=\"$0\" Dimensions=\"1 " + std::to_string(nodes) + "\" " + kInt64 +
         ">" + inline_item(std::to_string(nodes), kInt64, values) + "</DataItem>";
}

std::string attribute(const std::string& name, const char* center, const char* kind, const std::string& item) {
  return "     <Attribute Name=\"" + name + "\" Center=\"" + center + "\" AttributeType=\"" + kind + "\">" + item +
         "</Attribute>\n";
}

}  // namespace

std::string xdmf_description(const TrajectoryReader& reader, const std::string& h5_name, XdmfSummary* summary) {
  const std::size_t n = reader.frame_count(), N = reader.grain_count();
  // The values a picture cannot do without are checked as every program checks them:
  // radii and masses, and each frame's box (docs/file-format.md, Reading errors).
  reader.grains();
  for (std::size_t k = 0; k < n; ++k) {
    check_interrupt();
    reader.box(k);
  }
  const std::vector<double> times = reader.frame_times();
  std::vector<std::int64_t> offset(n + 1, 0);
  if (reader.has_contacts()) {
    const std::vector<double> stored = reader.array(schema::kFrameOffset);
    for (std::size_t k = 0; k <= n; ++k) offset[k] = std::int64_t(stored.at(k));
  }
  const std::size_t total = std::size_t(offset[n]);

  const Writer w(h5_name);
  const std::string value = "/value";
  const Source position{schema::kPosition + value, {n, N, 2}, kDouble};
  const Source velocity{schema::kVelocity + value, {n, N, 2}, kDouble};
  const Source orientation{schema::kOrientation + value, {n, N}, kDouble};
  const Source spin{schema::kAngularVelocity + value, {n, N}, kDouble};
  const Source edges{schema::kEdges + value, {n, 2, 2}, kDouble};
  const Source radius{schema::kGrains + "/radius", {N}, kDouble};
  const Source mass{schema::kGrains + "/mass", {N}, kDouble};
  const Source fixed{schema::kGrains + "/fixed", {N}, kUint8};
  const Source pair{schema::kContacts + "/pair", {total, 2}, kInt32};
  const Source branch{schema::kContacts + "/branch", {total, 2}, kDouble};
  const Source normal{schema::kContacts + "/normal_force", {total}, kDouble};
  const Source tangential{schema::kContacts + "/tangential_force", {total}, kDouble};
  const Source binary{schema::kContacts + "/binary_force", {total}, kDouble};
  const Source age{schema::kContacts + "/age", {total}, kInt64};

  auto grid_head = [&](const char* name, std::size_t k) {
    return "   <Grid Name=\"" + std::string(name) + "\" GridType=\"Uniform\">\n    <Time Value=\"" + number(times[k]) +
           "\"/>\n";
  };

  std::ostringstream x;
  x << "<?xml version=\"1.0\" ?>\n"
       "<!-- Written by gf-xdmf: a view of a granflow trajectory, every array a reference into it.\n"
       "     Open with ParaView's \"Xdmf Reader\" (docs/programs/gf-xdmf.md). -->\n"
       "<Xdmf Version=\"2.0\">\n <Domain>\n";

  // Grains: one vertex per grain at its stored centre.
  x << "  <Grid Name=\"grains\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (std::size_t k = 0; k < n; ++k) {
    x << grid_head("grains", k) << "    <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << N
      << "\" NodesPerElement=\"1\"/>\n"
      << "    <Geometry GeometryType=\"XY\">" << w.slab(position, {k, 0, 0}, {1, N, 2}, {N, 2}) << "</Geometry>\n"
      << attribute("radius", "Node", "Scalar", w.whole(radius)) << attribute("mass", "Node", "Scalar", w.whole(mass))
      << attribute("fixed", "Node", "Scalar", w.whole(fixed))
      << attribute("velocity", "Node", "Vector", w.slab(velocity, {k, 0, 0}, {1, N, 2}, {N, 2}))
      << attribute("angular_velocity", "Node", "Scalar", w.slab(spin, {k, 0}, {1, N}, {N}))
      << attribute("orientation", "Node", "Scalar", w.slab(orientation, {k, 0}, {1, N}, {N})) << "   </Grid>\n";
  }
  x << "  </Grid>\n";

  // Contacts: one segment per contact, from r_i to r_i − b (b = r_i − r_j the minimum
  // image), so a contact across a periodic or Lees–Edwards boundary reaches j's image
  // beside i instead of crossing the box. The points are computed by the reader from the
  // frame's positions, the pair's first grain and the branch vector; a frame with one
  // contact or none needs its own forms (an item of one element is a number, not an array,
  // in an XDMF 2 Function, and an empty item is an error).
  if (reader.has_contacts()) {
    x << "  <Grid Name=\"contacts\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t o = std::size_t(offset[k]), C = std::size_t(offset[k + 1] - offset[k]);
      x << grid_head("contacts", k);
      if (C == 0) {
        // No cell; the one point a grid needs sits on the box's corner.
        x << "    <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"0\" NodesPerElement=\"1\"/>\n"
          << "    <Geometry GeometryType=\"XY\">" << inline_item("1 2", kDouble, "0 0") << "</Geometry>\n   </Grid>\n";
        continue;
      }
      x << "    <Topology TopologyType=\"Polyline\" NumberOfElements=\"" << C << "\" NodesPerElement=\"2\">";
      if (C == 1) {
        const std::size_t i = std::size_t(reader.frame(k).contacts.pair.at(0)[0]);
        x << connectivity(2, "0 1") << "</Topology>\n"
          << "    <Geometry GeometryType=\"XY\"><DataItem ItemType=\"Function\" Function=\"$0 ; ($0 - $1)\" "
             "Dimensions=\"2 2\">"
          << w.slab(position, {k, i, 0}, {1, 1, 2}, {2}) << w.slab(branch, {o, 0}, {1, 2}, {2})
          << "</DataItem></Geometry>\n";
      } else {
        // Connectivity 0 1, 2 3, …: the indices of the frame's 2C pair entries (all ≥ 0).
        x << "<DataItem ItemType=\"Function\" Function=\"WHERE($0 &gt;= 0)\" Dimensions=\"" << C << " 2\" " << kInt64
          << ">" << w.slab(pair, {o, 0}, {C, 2}, {C, 2})
          << "</DataItem></Topology>\n"
          // Point 2c is r_i, point 2c+1 is r_i − b: x and y of both interlaced (spaces around
          // every operator: the expression scanner reads "+1" as a number).
          << "    <Geometry GeometryType=\"XY\"><DataItem ItemType=\"Function\" Function=\""
          << "($0[$1 * 2] , ($0[$1 * 2] - $2)) , ($0[$1 * 2 + 1] , ($0[$1 * 2 + 1] - $3))\" Dimensions=\"" << 2 * C
          << " 2\">" << w.slab(position, {k, 0, 0}, {1, N, 2}, {2 * N}) << w.slab(pair, {o, 0}, {C, 1}, {C})
          << w.slab(branch, {o, 0}, {C, 1}, {C}) << w.slab(branch, {o, 1}, {C, 1}, {C}) << "</DataItem></Geometry>\n";
      }
      x << attribute("normal_force", "Cell", "Scalar", w.slab(normal, {o}, {C}, {C}))
        << attribute("tangential_force", "Cell", "Scalar", w.slab(tangential, {o}, {C}, {C}))
        << attribute("binary_force", "Cell", "Scalar", w.slab(binary, {o}, {C}, {C}))
        << attribute("age", "Cell", "Scalar", w.slab(age, {o}, {C}, {C})) << "   </Grid>\n";
    }
    x << "  </Grid>\n";
  }

  // Box: the outline of the cell [0, Lx] × [0, Ly] the positions are wrapped into, from the
  // frame's edges [[Lx, 0], [δ, Ly]] (picked by index, the zeros by a mask), with δ, the
  // Lees–Edwards image offset, as the outline's cell value.
  x << "  <Grid Name=\"box\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (std::size_t k = 0; k < n; ++k) {
    x << grid_head("box", k) << "    <Topology TopologyType=\"Polyline\" NumberOfElements=\"1\" NodesPerElement=\"5\">"
      << connectivity(5, "0 1 2 3 0") << "</Topology>\n"
      << "    <Geometry GeometryType=\"XY\"><DataItem ItemType=\"Function\" Function=\"$0[$1] * $2\" "
         "Dimensions=\"4 2\">"
      << w.slab(edges, {k, 0, 0}, {1, 2, 2}, {4}) << inline_item("8", kInt64, "0 0 0 0 0 3 0 3")
      << inline_item("8", kDouble, "0 0 1 0 1 1 0 1") << "</DataItem></Geometry>\n"
      << attribute("offset", "Cell", "Scalar", w.slab(edges, {k, 1, 0}, {1, 1, 1}, {1})) << "   </Grid>\n";
  }
  x << "  </Grid>\n </Domain>\n</Xdmf>\n";

  if (summary) *summary = {n, N, total};
  return x.str();
}

}  // namespace granflow::io
