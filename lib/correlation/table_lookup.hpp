#pragma once
// ξ/ξ_el of gf-shear runs read from a gf-correlate table (made with --reference), matched by
// the sha256 of each run's file: what gf-network's predictions and gf-stz fit's dense rule
// need of chapter 5's correlation length.
#include <string>
#include <vector>

namespace granflow::correlation {

struct XiValue {
  double ratio = 0, error = 0;
  bool measurable = false;
};

// One value per run, in the order given. signed_xi: the table's xi_ratio (measurable when
// finite), else xi_abs_ratio with its `measurable` column. UsageError naming the file: not an
// HDF5 file, not a gf-correlate table, no ξ_el (made without --reference: `program` names
// who needs it in the message), a run it does not hold.
std::vector<XiValue> read_xi_ratios(const std::string& table, const std::vector<std::string>& runs, bool signed_xi,
                                    const std::string& program);

}  // namespace granflow::correlation
