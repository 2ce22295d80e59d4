#include "dynamics/lemke.hpp"

#include "dynamics/capacity.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace granflow {
namespace {

// An entry of the entering column counts as positive only above kPivot × the column's largest entry:
// below that it is the rounding of an exact zero, and dividing by it would wreck B⁻¹.
constexpr double kPivot = 1e-12;
// Two ratios tie when they differ by less than kTie × the sizes of the terms their numerators and
// denominators were summed from (Lemke::pivot). Exact ties (degenerate rows, duplicated contacts) come out
// of the arithmetic a few roundings apart, and breaking them by rounding instead of by the lexicographic
// rule lets the path cycle, or run onto a ray that the exact path avoids.
constexpr double kTie = 1e-11;
// Equilibration: log-least-squares sweeps, then max-norm sweeps at most (they stop once no factor changes).
constexpr int kLogSweeps = 5;
constexpr int kSweeps = 8;
// Acceptance of the polished z, relative to max|q| + max|M|·max|z|.
constexpr double kAccept = 1e-9;

// The power of two nearest 1/√size: a sweep scaling by it brings the size to within √2 of 1, exactly.
double equilibrating_factor(double size) {
  if (!(size > 0) || !std::isfinite(size)) return 1;
  return std::ldexp(1.0, -int(std::lround(0.5 * std::log2(size))));
}

}  // namespace

bool Lemke::solve(const Eigen::MatrixXd& M, const Eigen::VectorXd& q, Eigen::VectorXd& z, int max_pivots) {
  const int n = int(q.size());
  pivots_ = 0;
  if ((q.array() >= 0).all()) {
    z.setZero(n);
    return true;
  }
  // Sizes change only when n does, so repeated solves of one size allocate nothing here.
  equilibrate(M, q);
  value_ = scaled_q_;
  inverse_.setIdentity(n, n);
  column_.resize(n);
  update_.resize(n);
  entering_column_.resize(n);
  pivot_row_.resize(n);
  value_size_.resize(n);
  column_size_.resize(n);
  row_size_.resize(n);
  basic_.resize(n);
  row_of_.assign(2 * n + 1, -1);
  for (int i = 0; i < n; ++i) basic_[i] = row_of_[i] = i;
  tied_.reserve(n);
  support_.reserve(n);
  const int z0 = 2 * n;
  if (max_pivots < 1) return false;

  // z0 enters at the most negative q_r: the smallest z0 making w = q + z0·d ≥ 0. Ties go to the largest
  // index, the lexicographic choice with B⁻¹ = I (q_i + εⁱ is smallest for the largest i).
  int r = 0;
  for (int i = 1; i < n; ++i)
    if (value_(i) <= value_(r)) r = i;
  column_.setConstant(-1.0);
  int entering = z0;
  for (;;) {
    const int leaving = basic_[r];
    basic_[r] = entering;
    row_of_[entering] = r;
    row_of_[leaving] = -1;
    ++pivots_;
    // z0 out: the basis is complementary. polish() reads only which z_i are basic, so the tableau is left.
    if (leaving == z0) return polish(M, q, z);
    if (pivots_ >= max_pivots) return false;
    entering = leaving < n ? leaving + n : leaving - n;  // the complement of the variable that left
    if (entering < n) {
      entering_column_.setZero();  // w_j's column is e_j
      entering_column_(entering) = 1;
    } else {
      entering_column_ = -scaled_.col(entering - n);  // z_j's is −M_j
    }
    pivot(r);
    r = leaving_row(n);
    if (r < 0) return false;
  }
}

// Row and column factors D_r, D_c in powers of two, so that no entry is rounded: exact zeros, equal
// entries and duplicated rows stay so, and with them the problem's degeneracy. First a few sweeps of
// Curtis and Reid's log-least-squares scaling (each row, then each column, scaled by the geometric mean
// of its nonzeros): it finds the scaling that a structure such as the friction LCP's admits (W·s² next
// to entries 1 becomes W next to 1), which a max-norm balance alone does not when W is the small part,
// every row and column already holding an entry 1. Then Ruiz's max-norm sweeps bring every row and
// column's largest entry to within √2 of 1.
void Lemke::equilibrate(const Eigen::MatrixXd& M, const Eigen::VectorXd& q) {
  const int n = int(q.size());
  // Scratch taken from what solve() sets up next: log2|M| in inverse_ (−∞ for a zero), the sums and
  // counts of a sweep in value_ and scaled_q_, the exponents in row_scale_ and column_scale_.
  inverse_.resize(n, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double size = std::abs(M(i, j));
      inverse_(i, j) = size > 0 && std::isfinite(size) ? std::log2(size) : -std::numeric_limits<double>::infinity();
    }
  row_scale_.setZero(n);
  column_scale_.setZero(n);
  value_.resize(n);
  scaled_q_.resize(n);
  for (int sweep = 0; sweep < kLogSweeps; ++sweep) {
    value_.setZero();
    scaled_q_.setZero();
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        if (std::isfinite(inverse_(i, j))) {
          value_(i) += inverse_(i, j) + column_scale_(j);
          scaled_q_(i) += 1;
        }
    for (int i = 0; i < n; ++i) row_scale_(i) = scaled_q_(i) > 0 ? -value_(i) / scaled_q_(i) : 0;
    for (int j = 0; j < n; ++j) {
      double sum = 0, count = 0;
      for (int i = 0; i < n; ++i)
        if (std::isfinite(inverse_(i, j))) {
          sum += inverse_(i, j) + row_scale_(i);
          count += 1;
        }
      column_scale_(j) = count > 0 ? -sum / count : 0;
    }
  }
  for (int i = 0; i < n; ++i) row_scale_(i) = std::ldexp(1.0, int(std::lround(row_scale_(i))));
  for (int j = 0; j < n; ++j) column_scale_(j) = std::ldexp(1.0, int(std::lround(column_scale_(j))));
  scaled_.noalias() = row_scale_.asDiagonal() * M * column_scale_.asDiagonal();

  for (int sweep = 0; sweep < kSweeps; ++sweep) {
    scaled_q_.setZero();  // the rows' largest |entries|, then their factors
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) scaled_q_(i) = std::max(scaled_q_(i), std::abs(scaled_(i, j)));
    bool changed = false;
    for (int i = 0; i < n; ++i) {
      scaled_q_(i) = equilibrating_factor(scaled_q_(i));
      changed = changed || scaled_q_(i) != 1;
    }
    scaled_.array().colwise() *= scaled_q_.array();
    row_scale_.array() *= scaled_q_.array();
    for (int j = 0; j < n; ++j) {
      const double factor = equilibrating_factor(scaled_.col(j).cwiseAbs().maxCoeff());
      changed = changed || factor != 1;
      scaled_.col(j) *= factor;
      column_scale_(j) *= factor;
    }
    if (!changed) break;
  }
  scaled_q_ = row_scale_.cwiseProduct(q);
}

// Gauss–Jordan step on row r: B⁻¹ ← E·B⁻¹ with E = I − (a − e_r)·e_rᵀ / a_r, a the entering column,
// a rank-one update of B⁻¹ and of the values. The same sweep through B⁻¹ forms the next entering column
// a = B⁻¹·A_j (entering_column_ holds A_j) and, row by row, the sizes of the terms each value and each
// entry of a is a sum of: |B⁻¹|·|D_r·q| and |B⁻¹|·|A_j|. Their roundings are a few units in the last
// place of these sizes, whatever the cancellation, and in each row's own units, whatever the scaling.
void Lemke::pivot(int r) {
  const int n = int(value_.size());
  const double p = column_(r);
  pivot_row_ = inverse_.row(r).transpose() / p;
  const double step = value_(r) / p;
  column_(r) -= 1.0;
  // A degenerate step (value 0) leaves the other values bit for bit, so their exact zeros stay exact.
  if (step != 0) value_ -= step * column_;
  value_(r) = step;
  update_.swap(column_);
  column_.setZero();
  value_size_.setZero();
  column_size_.setZero();
  // Column by column, so that each column of B⁻¹ is read from memory once and the rest runs in cache;
  // the zeros skipped are common (pivot rows of B⁻¹, degenerate q, sparse columns of M).
  for (int j = 0; j < n; ++j) {
    auto b = inverse_.col(j);
    const double v = pivot_row_(j), entry = entering_column_(j), q_size = std::abs(scaled_q_(j));
    if (v != 0) b -= v * update_;
    if (q_size != 0) value_size_ += q_size * b.cwiseAbs();
    if (entry != 0) {
      column_ += entry * b;
      column_size_ += std::abs(entry) * b.cwiseAbs();
    }
  }
}

// Lexicographic minimum-ratio test: among rows with a positive entry a_i, the lexicographically smallest
// (value_i, B⁻¹_i,·) / a_i. The rows of [value | B⁻¹] stay lexicographically positive, so every basis
// is visited at most once. When z0's row is among the ties of the value ratio it is taken: z0 leaves at
// once and the path ends at a solution.
int Lemke::leaving_row(int n) {
  double largest = 0;
  for (int i = 0; i < n; ++i) largest = std::max(largest, std::abs(column_(i)));
  if (!(largest > 0) || !std::isfinite(largest)) return -1;
  const double positive = kPivot * largest;
  double theta = std::numeric_limits<double>::infinity();
  int first = -1;
  for (int i = 0; i < n; ++i) {
    // A value a rounding below zero is a degenerate zero.
    const double ratio = std::max(value_(i), 0.0) / column_(i);
    if (column_(i) > positive && ratio < theta) {
      theta = ratio;
      first = i;
    }
  }
  if (first < 0) return -1;  // secondary ray
  // Row i ties with the first minimum k when x_i − θ·a_i, which is 0 for an exact tie, is within the
  // roundings of x_i, of θ·a_i and of θ = x_k/a_k (times a_i). Compared so rather than as ratios: a small
  // a_i magnifies the rounding of x_i in x_i/a_i, and that is still a tie.
  const auto slack = [&](int i, double ratio, double size) { return size + ratio * column_size_(i); };
  double base = slack(first, theta, value_size_(first)) / column_(first);
  tied_.clear();
  for (int i = 0; i < n; ++i)
    if (i == first || (column_(i) > positive && std::max(value_(i), 0.0) - theta * column_(i) <=
                                                    kTie * (slack(i, theta, value_size_(i)) + column_(i) * base)))
      tied_.push_back(i);
  if (tied_.size() == 1) return tied_[0];
  const int z0_row = row_of_[2 * n];
  if (z0_row >= 0 && std::find(tied_.begin(), tied_.end(), z0_row) != tied_.end()) return z0_row;
  // Break the ties on the columns of B⁻¹ in turn; B⁻¹ is nonsingular, so its rows differ somewhere. The
  // entries of row i of B⁻¹ are known to the rounding of Σ_j |B⁻¹_ij| (the rows' sizes, only now needed).
  for (int i : tied_) row_size_(i) = inverse_.row(i).cwiseAbs().sum();
  for (int c = 0; c < n && tied_.size() > 1; ++c) {
    double least = std::numeric_limits<double>::infinity();
    for (int i : tied_)
      if (inverse_(i, c) / column_(i) < least) {
        least = inverse_(i, c) / column_(i);
        first = i;
      }
    base = slack(first, std::abs(least), row_size_(first)) / column_(first);
    std::erase_if(tied_, [&](int i) {
      return i != first &&
             inverse_(i, c) - least * column_(i) > kTie * (slack(i, std::abs(least), row_size_(i)) + column_(i) * base);
    });
  }
  // Rows equal to the tolerance all through: the largest pivot is the most accurate.
  return *std::max_element(tied_.begin(), tied_.end(), [&](int i, int k) { return column_(i) < column_(k); });
}

// The final basis fixes S = {i : z_i basic} and w_S = 0; z_S is solved again from M and q, which removes
// the rounding the pivots accumulated in B⁻¹. The basis was nonsingular, hence M[S, S] is. The system
// solved is the equilibrated one, D_r·M·D_c and D_r·q, equal to the original to the last bit (powers of
// two) but without the spread of sizes that would make FullPivLU's rank threshold drop a small pivot that
// matters (friction rows of size 1 next to W of size 10⁶).
bool Lemke::polish(const Eigen::MatrixXd& M, const Eigen::VectorXd& q, Eigen::VectorXd& z) {
  const int n = int(q.size());
  support_.clear();
  for (int i = 0; i < n; ++i)
    if (row_of_[n + i] >= 0) support_.push_back(i);
  const int s = int(support_.size());
  column_.setZero();  // free now: z' = D_c⁻¹·z, the equilibrated unknowns
  if (s > 0) {
    // M[S, S] in the top-left corner of B⁻¹'s storage, no longer needed: no allocation for any |S|.
    for (int b = 0; b < s; ++b) {
      for (int a = 0; a < s; ++a) inverse_(a, b) = scaled_(support_[a], support_[b]);
      update_(b) = -scaled_q_(support_[b]);
    }
    Eigen::Ref<Eigen::MatrixXd> block(inverse_.topLeftCorner(s, s));
    Eigen::FullPivLU<Eigen::Ref<Eigen::MatrixXd>> lu(block);  // factorised in place
    pivot_row_.head(s) = lu.solve(update_.head(s));
    for (int b = 0; b < s; ++b) column_(support_[b]) = pivot_row_(b);
  }
  // Checked in both units: the caller's tolerance is the caller's, and the equilibrated one does not let
  // the rows of large entries set the tolerance of the rows of small ones.
  if (!complementary(scaled_, scaled_q_, column_)) return false;
  z = column_scale_.cwiseProduct(column_);
  return complementary(M, q, z);
}

// z ≥ 0, w = A·z + b ≥ 0 and zᵢ·wᵢ = 0 to tol = kAccept·(max|b| + max|A|·max|z|); negative z_i within tol
// are set to 0. zᵢ·wᵢ scales as z², so it is measured against tol·max|z|.
bool Lemke::complementary(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, Eigen::VectorXd& z) {
  const double z_max = z.cwiseAbs().maxCoeff();
  const double tol = kAccept * (b.cwiseAbs().maxCoeff() + A.cwiseAbs().maxCoeff() * z_max);
  // Comparisons written so that a NaN fails them.
  for (int i = 0; i < z.size(); ++i) {
    if (!(z(i) >= -tol)) return false;
    z(i) = std::max(z(i), 0.0);
  }
  residual_.noalias() = A * z;
  residual_ += b;
  for (int i = 0; i < z.size(); ++i)
    if (!(residual_(i) >= -tol) || !(std::abs(z(i) * residual_(i)) <= tol * z_max)) return false;
  return true;
}

std::size_t Lemke::bytes() const {
  const auto doubles = [](const auto& m) { return std::size_t(m.size()) * sizeof(double); };
  return doubles(scaled_) + doubles(scaled_q_) + doubles(row_scale_) + doubles(column_scale_) + doubles(inverse_) +
         doubles(value_) + doubles(value_size_) + doubles(column_size_) + doubles(row_size_) + doubles(column_) +
         doubles(update_) + doubles(entering_column_) + doubles(pivot_row_) + doubles(residual_) + heap_bytes(basic_) +
         heap_bytes(row_of_) + heap_bytes(tied_) + heap_bytes(support_);
}

}  // namespace granflow
