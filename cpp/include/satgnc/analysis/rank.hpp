#pragma once
/// @file rank.hpp
/// Controllability and observability rank tests that return a report, not a bool: an orthogonal
/// staircase reduction (SVD or QR with column pivoting per stair), the PBH test per (clustered)
/// eigenvalue with stabilizability / detectability, the Kalman matrix (display and comparison only),
/// distance to uncontrollability, and the actuator / sensor-loss table.
///
/// Tolerances are relative. Staircase: stair 1 is judged against ||B||_F, every later stair against
/// ||A||_F, so the verdict is invariant under time scaling (A, B -> s A, s B), input scaling and
/// orthogonal similarity. Diagonal state scaling (units) is not an orthogonal similarity: use
/// RankSettings::units for a dimensionless model (time 1/omega, length sigma).
/// Observability is tested by duality (A^T, C^T). These are analysis-time tools: they allocate.
#include <Eigen/Core>
#include <complex>
#include <optional>
#include <string>
#include <vector>

#include "satgnc/analysis/linearize.hpp"
#include "satgnc/core/status.hpp"

namespace satgnc::analysis {

/// Which property a report is about.
enum class Property { controllability = 0, observability };

/// Verdict of a rank test (core/status.hpp; an intended exception to "unsolved first": a verdict,
/// not a run outcome). full_rank: controllable / observable, with margin >= fuzz; rank_deficient:
/// uncontrollable / unobservable, with margin >= fuzz; not_robustly_decidable: a singular value sits
/// in the fuzz band, or the verdict hinges on data entries below the tolerance (RankReport::reason).
using core::status_message;
using core::status_name;
using core::Verdict;

/// "full rank", "rank deficient", "not robustly decidable" (the table's message).
[[deprecated("use status_message")]] inline const char* verdict_name(Verdict v) {
  return core::status_message(v);
}
/// "controllable" / "uncontrollable" / "observable" / ... / "not robustly decidable".
const char* verdict_text(Verdict v, Property p);

/// Per-stair rank decision: SVD (default) or Householder QR with column pivoting.
enum class StairMethod { svd = 0, qrcp };

/// Settings of every rank test (plain struct; defaults documented per field).
struct RankSettings {
  /// Relative rank tolerance (>= 0). 0 selects the method's default: staircase and PBH
  /// 10 max(n, m) eps; Kalman max(rows, cols) eps (numpy.linalg.matrix_rank's default).
  double rtol = 0.0;
  /// Fuzz band factor (> 1): a verdict is robust only if the smallest accepted (relative) singular
  /// value is >= fuzz * rtol. Default 100.
  double fuzz = 100.0;
  StairMethod stair = StairMethod::svd;  ///< staircase per-stair decomposition
  /// PBH eigenvalue clustering radius relative to ||A||_F (>= 0). Default 1e-6: merges the split
  /// pair of a defective (Jordan) eigenvalue, e.g. the zero pair of the polar and CW models.
  double cluster_rtol = 1e-6;
  /// Optional units: the test runs on the nondimensionalized model (see nondimensionalize()).
  std::optional<Units> units;
  /// Throw std::invalid_argument on negative / non-finite rtol, fuzz <= 1, negative cluster_rtol.
  void validate() const;
};

/// What every rank test returns.
struct RankReport {
  Property property = Property::controllability;
  int n = 0;                ///< state dimension
  int rank = 0;             ///< numerical rank (dimension of the controllable / observable subspace)
  double rtol = 0.0;        ///< relative tolerance used
  double sigma_r = 0.0;     ///< smallest accepted singular value (relative); inf if none accepted
  double sigma_next = 0.0;  ///< largest rejected singular value (relative); 0 if none rejected
  double margin = 0.0;      ///< sigma_r / rtol
  double gap = 0.0;         ///< sigma_r / sigma_next (inf when sigma_next = 0)
  std::string method;       ///< "staircase-svd", "staircase-qrcp", "pbh", "kalman-svd"
  Verdict verdict = Verdict::not_robustly_decidable;
  std::string reason;  ///< why the verdict is not robust (empty when it is)
};

/// Staircase (controllability / observability) form and what it reveals.
struct StaircaseReport {
  RankReport summary;
  std::vector<int> stairs;   ///< stair sizes; their sum is the rank
  std::vector<int> indices;  ///< controllability (observability) indices, descending
  /// n x n orthogonal. Controllability: the first `rank` columns span the controllable subspace.
  /// Observability: the first `rank` columns span the row space of the observability matrix, the
  /// remaining columns the unobservable subspace.
  Eigen::MatrixXd Q;
  Eigen::MatrixXd A_staircase;            ///< Q^T A Q (observability: Q^T A^T Q, the dual)
  Eigen::MatrixXd B_staircase;            ///< Q^T B (observability: Q^T C^T)
  Eigen::MatrixXd A_uncontrollable;       ///< trailing (n - rank) block (unobservable block if dual)
  Eigen::VectorXcd uncontrollable_modes;  ///< its eigenvalues (unobservable modes if dual)
};

/// Orthogonal staircase reduction of (A, B) (controllability) or of (A^T, C^T) (observability;
/// pass C as `BC`). Throws std::invalid_argument on bad shapes, empty B/C, non-finite data.
StaircaseReport staircase(const Eigen::MatrixXd& A, const Eigen::MatrixXd& BC, Property p,
                          const RankSettings& s = {});

/// One (clustered) eigenvalue in the PBH test.
struct PbhMode {
  std::complex<double> lambda;  ///< eigenvalue (cluster mean), 1/s
  int multiplicity = 1;         ///< number of computed eigenvalues merged into the cluster
  double sigma_min = 0.0;       ///< sigma_min([A - lambda I, B]) / ||[A B]||_F
  int deficiency = 0;           ///< singular values of [A - lambda I, B] below rtol
  bool controllable = true;     ///< deficiency == 0 (observable for the dual)
  bool ct_stable = false;       ///< Re lambda < 0 (beyond the cluster radius)
  bool dt_stable = false;       ///< |lambda| < 1 (beyond the cluster radius)
  Verdict verdict = Verdict::full_rank;
};

/// PBH test per eigenvalue.
struct PbhReport {
  RankReport summary;  ///< rank = n - sum of deficiencies
  std::vector<PbhMode> modes;
  bool stabilizable_ct = false;       ///< every mode with Re >= 0 controllable (detectable for the dual)
  bool stabilizable_dt = false;       ///< every mode with |lambda| >= 1 controllable
  double distance_upper_bound = 0.0;  ///< min over eigenvalues of sigma_min([A - lambda I, B]) (abs)
};

/// PBH: rank of [A - lambda I, B] for every eigenvalue cluster, tolerance rtol ||[A B]||_F.
PbhReport pbh(const Eigen::MatrixXd& A, const Eigen::MatrixXd& BC, Property p, const RankSettings& s = {});

/// Kalman matrix [B, AB, ..., A^{n-1} B] (n x nm), for display and the paper comparison.
Eigen::MatrixXd kalman_controllability_matrix(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B);
/// Kalman matrix [C; CA; ...; C A^{n-1}] (np x n).
Eigen::MatrixXd kalman_observability_matrix(const Eigen::MatrixXd& A, const Eigen::MatrixXd& C);
/// Rank of the Kalman matrix by SVD, tolerance rtol * sigma_max (comparison only: it squares the
/// dynamic range of A per power and misjudges at orbital rates).
RankReport kalman_rank(const Eigen::MatrixXd& A, const Eigen::MatrixXd& BC, Property p,
                       const RankSettings& s = {});

/// Distance to uncontrollability min_{lambda in C} sigma_min([A - lambda I, B]) (Eising).
struct DistanceReport {
  double upper_bound = 0.0;             ///< min over eigenvalues (PBH), absolute
  std::complex<double> lambda_upper;    ///< where
  double refined = 0.0;                 ///< after local Nelder-Mead over complex lambda (<= upper)
  std::complex<double> lambda_refined;  ///< where
  double relative = 0.0;                ///< refined / ||[A B]||_F
  int evaluations = 0;                  ///< sigma_min evaluations
  std::string method;
};
/// Upper bound from the eigenvalues, then Nelder-Mead in (Re, Im) from every eigenvalue cluster.
/// Observability: the distance to unobservability of (A, C) by duality.
DistanceReport distance_to_uncontrollability(const Eigen::MatrixXd& A, const Eigen::MatrixXd& BC,
                                             Property p = Property::controllability,
                                             const RankSettings& s = {}, int max_iter = 200);

/// One row of the actuator / sensor-loss table.
struct LossRow {
  std::vector<int> channels;  ///< kept inputs (controllability) or outputs (observability), 0-based
  int rank = 0;               ///< staircase rank
  Verdict verdict = Verdict::not_robustly_decidable;
  double margin = 0.0;        ///< staircase margin
  int kalman_rank = 0;        ///< Kalman-matrix rank (numpy's default tolerance), for comparison
  double kalman_ratio = 0.0;  ///< sigma_min / sigma_max of the Kalman matrix
};
/// Every non-empty subset of the columns of B (controllability) or rows of C (observability), the
/// full set first, then by decreasing size, lexicographic. At most 16 channels.
std::vector<LossRow> loss_table(const Eigen::MatrixXd& A, const Eigen::MatrixXd& BC, Property p,
                                const RankSettings& s = {});

}  // namespace satgnc::analysis
