#pragma once
// ξ/ξ_el of gf-shear runs read from a gf-correlate table (made with --reference), matched by
// the sha256 of each run's file: what gf-network's predictions and gf-stz fit's dense rule
// need of chapter 5's correlation length.
#include <optional>
#include <string>
#include <vector>

namespace granflow::correlation {

struct XiValue {
  double ratio = 0, error = 0;
  bool measurable = false;
};

// Which ξ/ξ_el of the table: abs = xi_abs_ratio with its `measurable` column; signed =
// xi_ratio (eq. 5.2, C per unit area) and signed_length = xi_length_ratio (eq. 5.2, C per unit
// length), each measurable when finite.
enum class XiReading { abs, signed_area, signed_length };

// The option value naming a reading ("abs", "signed", "signed-length"), and back (nullopt for
// any other text); the table's ratio dataset ("xi_abs_ratio", ...).
const char* xi_reading_name(XiReading reading);
std::optional<XiReading> parse_xi_reading(const std::string& name);
const char* xi_ratio_dataset(XiReading reading);

// One value per run, in the order given. UsageError naming the file: not an HDF5 file, not a
// gf-correlate table, no ξ_el (made without --reference: `program` names who needs it in the
// message), a run it does not hold.
std::vector<XiValue> read_xi_ratios(const std::string& table, const std::vector<std::string>& runs, XiReading reading,
                                    const std::string& program);

}  // namespace granflow::correlation
