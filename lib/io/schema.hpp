#pragma once
// The trajectory layout shared by the writer and the reader, in one place, so the two
// cannot drift apart (docs/file-format.md, Names and units).
#include <string>
#include <vector>

#include "io/hdf5_handle.hpp"
#include "io/trajectory.hpp"

namespace granflow::io::schema {

inline const std::string kH5md = "/h5md";
inline const std::string kParameters = "/parameters";
inline const std::string kParticles = "/particles";
inline const std::string kGrains = "/particles/grains";
inline const std::string kBox = "/particles/grains/box";
inline const std::string kLeesEdwards = "/lees_edwards";
inline const std::string kContacts = "/contacts";
inline const std::string kFrameOffset = "/contacts/frame_offset";
inline const std::string kObservables = "/observables";
// Root attribute of a run still being written or interrupted (readers refuse it).
inline const std::string kUnfinished = "unfinished";
inline const std::string kPosition = "/particles/grains/position";
inline const std::string kVelocity = "/particles/grains/velocity";
inline const std::string kOrientation = "/particles/grains/orientation";
inline const std::string kAngularVelocity = "/particles/grains/angular_velocity";
inline const std::string kEdges = "/particles/grains/box/edges";
inline const std::string kOffset = "/lees_edwards/offset";

// An H5MD time-dependent element written once per frame: its group path and the
// shape of one frame's value.
struct FrameElement {
  std::string path;
  std::vector<hsize_t> inner;
  std::string inner_text;  // the shape for messages, e.g. "[grains][2]"
  std::string quantity;    // what its value is, in the words of io::unit_of
};
// Every per-frame element of a trajectory of `grains` grains; the Lees–Edwards
// offset only for boxes periodic in y.
std::vector<FrameElement> frame_elements(hsize_t grains, bool periodic_y);

// One column of the flat contact table: name under /contacts, types, the shape of a
// row, and how to reach its storage in a ContactRecords.
struct ContactColumn {
  std::string name;
  hid_t file_type, mem_type;
  std::vector<hsize_t> inner;
  std::size_t (*size)(const ContactRecords&);
  const void* (*data)(const ContactRecords&);
  void* (*resize)(ContactRecords&, std::size_t rows);  // returns the storage
  std::string quantity;                                // in the words of io::unit_of
};
const std::vector<ContactColumn>& contact_columns();

// What each observable the programs record is, in the words of io::unit_of
// (docs/file-format.md, Observables); RuntimeFailure for a name it does not know.
const std::string& observable_quantity(const std::string& name);

// Rows per tensor observable: [2][2], row-major (value[i][j] = T_ij).
inline const std::vector<hsize_t> kTensorShape{2, 2};

// Whether the box is periodic in y, from /particles/grains/box's boundary attribute;
// Hdf5Error if the attribute is not ["periodic", "periodic" | "none"] or dimension ≠ 2.
bool read_periodic_y(hid_t file);

}  // namespace granflow::io::schema
