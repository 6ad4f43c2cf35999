#include "satgnc/analysis/rank.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>

#include "satgnc/core/validate.hpp"

namespace satgnc::analysis {

using Eigen::MatrixXcd;
using Eigen::MatrixXd;
using Eigen::VectorXcd;
using Eigen::VectorXd;
using cplx = std::complex<double>;

namespace {
constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kInf = std::numeric_limits<double>::infinity();
}  // namespace

const char* verdict_text(Verdict v, Property p) {
  const bool c = p == Property::controllability;
  switch (v) {
    case Verdict::full_rank:
      return c ? "controllable" : "observable";
    case Verdict::rank_deficient:
      return c ? "uncontrollable" : "unobservable";
    case Verdict::not_robustly_decidable:
      return "not robustly decidable";
  }
  return "unknown";
}

void RankSettings::validate() const {
  core::require_nonnegative(rtol, "rtol");
  core::require(std::isfinite(fuzz) && fuzz > 1.0, "fuzz", "must be finite and > 1");
  core::require_nonnegative(cluster_rtol, "cluster_rtol");
}

namespace {

// Validated (A, B) for the controllability question: observability goes through the dual, and the
// optional units are applied first.
struct Pair {
  MatrixXd A, B;
};

Pair prepare(const MatrixXd& A, const MatrixXd& BC, Property p, const RankSettings& s) {
  s.validate();
  core::require(
      A.rows() > 0 && A.rows() == A.cols(), "A",
      "must be square and non-empty, got " + std::to_string(A.rows()) + "x" + std::to_string(A.cols()));
  core::require_finite(A, "A");
  const Eigen::Index n = A.rows();
  LinearModel m;
  m.A = A;
  if (p == Property::controllability) {
    core::require(BC.cols() > 0, "B", "needs at least one input column (empty input set)");
    core::require(BC.rows() == n, "B",
                  "must have n = " + std::to_string(n) + " rows, got " + std::to_string(BC.rows()));
    core::require_finite(BC, "B");
    m.B = BC;
    m.C = MatrixXd(0, n);
  } else {
    core::require(BC.rows() > 0, "C", "needs at least one output row (empty output set)");
    core::require(BC.cols() == n, "C",
                  "must have n = " + std::to_string(n) + " columns, got " + std::to_string(BC.cols()));
    core::require_finite(BC, "C");
    m.C = BC;
    m.B = MatrixXd(n, 0);
  }
  if (s.units) {  // only the units of the channels under test matter
    Units u = *s.units;
    (p == Property::controllability ? u.output : u.input).resize(0);
    m = nondimensionalize(m, u);
  }
  if (p == Property::controllability) return {m.A, m.B};
  return {m.A.transpose(), m.C.transpose()};
}

double default_rtol(const RankSettings& s, Eigen::Index n, Eigen::Index m) {
  return s.rtol > 0.0 ? s.rtol : 10.0 * static_cast<double>(std::max(n, m)) * kEps;
}

double safe_norm(const MatrixXd& M) {
  const double v = M.norm();
  return v > 0.0 ? v : 1.0;
}

// Nonzero entries below rtol * norm: information the rounding of a rank decision cannot see.
int count_subtolerance(const MatrixXd& M, double thresh) {
  int c = 0;
  for (Eigen::Index j = 0; j < M.cols(); ++j)
    for (Eigen::Index i = 0; i < M.rows(); ++i)
      if (M(i, j) != 0.0 && std::abs(M(i, j)) <= thresh) ++c;
  return c;
}

void finish(RankReport& r, double margin) {
  r.margin = margin >= 0.0 ? margin : r.sigma_r / r.rtol;
  r.gap = r.sigma_next > 0.0 ? r.sigma_r / r.sigma_next : kInf;
}

std::string fmt(double v) {
  std::ostringstream os;
  os.precision(3);
  os << v;
  return os.str();
}

// Shared verdict rule: robust iff the smallest accepted relative singular value is >= fuzz * rtol
// and, for a deficient rank, no nonzero data entry lies below the tolerance.
void decide(RankReport& r, double fuzz, int subtol_entries, double margin = -1.0) {
  finish(r, margin);
  r.reason.clear();
  if (r.margin < fuzz) {
    r.verdict = Verdict::not_robustly_decidable;
    r.reason = "margin " + fmt(r.margin) + " < fuzz " + fmt(fuzz) +
               ": an accepted singular value is too close to the tolerance or to its rounding noise";
    return;
  }
  if (r.rank < r.n && subtol_entries > 0) {
    r.verdict = Verdict::not_robustly_decidable;
    r.reason = std::to_string(subtol_entries) +
               " nonzero data entries are below the tolerance: perturbing them by their own size "
               "changes the rank";
    return;
  }
  r.verdict = r.rank == r.n ? Verdict::full_rank : Verdict::rank_deficient;
}

// Householder reflectors (hv, hc) of an orthogonal H (rows x rows) whose leading columns span the
// dominant left singular directions of `block` (so H^T block is zero below its rank), and the
// rank-revealing values (singular values or |R_ii|), descending. O(rows cols^2 + rows cols^2).
void compress(const MatrixXd& block, StairMethod method, MatrixXd& hv, VectorXd& hc, VectorXd& values) {
  const Eigen::Index k = std::min(block.rows(), block.cols());
  if (block.cols() == 1) {
    // One column: its norm is the singular value and one reflector maps it onto e1.
    hv.resize(block.rows(), 1);
    hc.resize(1);
    values.resize(1);
    double beta;
    hv.col(0) = block.col(0);
    if (block.rows() > 1) {
      Eigen::VectorXd ess(block.rows() - 1);
      block.col(0).makeHouseholder(ess, hc(0), beta);
      hv.col(0).tail(block.rows() - 1) = ess;
    } else {
      hc(0) = 0.0;
      beta = block(0, 0);
    }
    values(0) = std::abs(beta);
    return;
  }
  if (method == StairMethod::svd) {
    Eigen::JacobiSVD<MatrixXd> svd(block, Eigen::ComputeThinU);
    values = svd.singularValues();
    Eigen::HouseholderQR<MatrixXd> qr(svd.matrixU().leftCols(k));
    hv = qr.matrixQR();
    hc = qr.hCoeffs();
  } else {
    Eigen::ColPivHouseholderQR<MatrixXd> qr(block);
    values = qr.matrixQR().diagonal().head(k).cwiseAbs();
    hv = qr.matrixQR().leftCols(k);
    hc = qr.hCoeffs().head(k);
  }
}

// The summary fields staircase() and pbh() set before their first rank decision (n states, m
// inputs or outputs of the prepared pair).
void init_summary(RankReport& rep, Property p, Eigen::Index n, Eigen::Index m, const RankSettings& s,
                  const char* method) {
  rep.property = p;
  rep.n = static_cast<int>(n);
  rep.rtol = default_rtol(s, n, m);
  rep.method = method;
  rep.sigma_r = kInf;
  rep.sigma_next = 0.0;
}

}  // namespace

StaircaseReport staircase(const MatrixXd& A_in, const MatrixXd& BC, Property p, const RankSettings& s) {
  const Pair pr = prepare(A_in, BC, p, s);
  const Eigen::Index n = pr.A.rows(), m = pr.B.cols();
  StaircaseReport out;
  RankReport& rep = out.summary;
  init_summary(rep, p, n, m, s, s.stair == StairMethod::svd ? "staircase-svd" : "staircase-qrcp");
  double min_margin = kInf;

  const double normA = safe_norm(pr.A), normB = safe_norm(pr.B);
  // Lane 0 is the data; lane 1 is the data plus a random perturbation of rounding size
  // (n eps ||.||_F). All lanes share the stair decisions, so the spread of each stair's singular
  // values across lanes measures how much rounding the chain of earlier stairs amplifies into it
  // (the Krylov-chain sensitivity that a fixed tolerance cannot see).
  constexpr int kLanes = 2;
  constexpr double kNoise = 10.0;               // a value must exceed kNoise x its measured spread to count
  std::uint64_t state = 0x9E3779B97F4A7C15ull;  // fixed seed: reproducible reports
  auto uniform = [&state]() {  // splitmix64 -> [-1, 1): cheap, and the shape does not matter here
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return static_cast<double>(z >> 11) * 0x1.0p-52 - 1.0;
  };
  MatrixXd Ab[kLanes], Bb[kLanes];
  for (int l = 0; l < kLanes; ++l) {
    Ab[l] = pr.A;
    Bb[l] = pr.B;
    if (l == 0) continue;
    MatrixXd E = MatrixXd::NullaryExpr(n, n, uniform);
    MatrixXd F = MatrixXd::NullaryExpr(n, m, uniform);
    Ab[l] += (static_cast<double>(n) * kEps * normA / E.norm()) * E;
    Bb[l] += (static_cast<double>(n) * kEps * normB / F.norm()) * F;
  }
  MatrixXd Q = MatrixXd::Identity(n, n);
  Eigen::Index pos = 0, prev = 0;  // states already in the controllable part; previous stair size
  MatrixXd hv[kLanes];
  VectorXd hc[kLanes], vals[kLanes];
  for (int k = 0; pos < n; ++k) {
    const Eigen::Index rows = n - pos;
    const double norm = k == 0 ? normB : normA;
    for (int l = 0; l < kLanes; ++l) {
      const MatrixXd block = k == 0 ? Bb[l] : MatrixXd(Ab[l].block(pos, pos - prev, rows, prev));
      compress(block, s.stair, hv[l], hc[l], vals[l]);
    }
    Eigen::Index r = 0;
    for (Eigen::Index i = 0; i < vals[0].size(); ++i) {
      double spread = 0.0;
      for (int l = 1; l < kLanes; ++l) spread = std::max(spread, std::abs(vals[l](i) - vals[0](i)));
      const double noise = std::max(rep.rtol * norm, kNoise * spread);
      const double rel = vals[0](i) / norm;
      if (vals[0](i) > noise && r == i) {
        ++r;
        rep.sigma_r = std::min(rep.sigma_r, rel);
        min_margin = std::min(min_margin, vals[0](i) / noise);
      } else {
        rep.sigma_next = std::max(rep.sigma_next, rel);
      }
    }
    if (r == 0) break;
    for (int l = 0; l < kLanes; ++l) {
      const Eigen::HouseholderSequence<MatrixXd, VectorXd> H(hv[l], hc[l]);
      auto Abot = Ab[l].bottomRows(rows);
      auto Aright = Ab[l].rightCols(rows);
      auto Bbot = Bb[l].bottomRows(rows);
      Abot.applyOnTheLeft(H.transpose());
      Aright.applyOnTheRight(H);
      Bbot.applyOnTheLeft(H.transpose());
      if (l == 0) {
        auto Qright = Q.rightCols(rows);
        Qright.applyOnTheRight(H);
      }
      // Exact staircase shape: what lies below the stair is rounding (or rejected) mass.
      if (k == 0)
        Bb[l].bottomRows(rows - r).setZero();
      else
        Ab[l].block(pos + r, pos - prev, rows - r, prev).setZero();
    }
    out.stairs.push_back(static_cast<int>(r));
    prev = r;
    pos += r;
  }
  MatrixXd& A0 = Ab[0];
  MatrixXd& B0 = Bb[0];
  // The block below the last stair is the (rejected) coupling into the uncontrollable part.
  if (pos < n && prev > 0) A0.block(pos, pos - prev, n - pos, prev).setZero();
  if (pos < n && out.stairs.empty()) B0.setZero();
  rep.rank = static_cast<int>(pos);
  if (!out.stairs.empty())
    for (int j = 1; j <= out.stairs.front(); ++j) {
      int c = 0;
      for (int st : out.stairs) c += st >= j ? 1 : 0;
      out.indices.push_back(c);
    }
  out.Q = Q;
  out.A_staircase = A0;
  out.B_staircase = B0;
  out.A_uncontrollable = A0.bottomRightCorner(n - pos, n - pos);
  if (n - pos > 0) {
    Eigen::EigenSolver<MatrixXd> es(out.A_uncontrollable, false);
    out.uncontrollable_modes = es.eigenvalues();
  } else {
    out.uncontrollable_modes.resize(0);
  }
  const int subtol = count_subtolerance(pr.A, rep.rtol * normA) + count_subtolerance(pr.B, rep.rtol * normB);
  decide(rep, s.fuzz, subtol, min_margin);
  return out;
}

namespace {

struct Cluster {
  cplx mean;
  std::vector<cplx> members;
};

std::vector<Cluster> cluster_eigenvalues(const VectorXcd& ev, double radius) {
  std::vector<Cluster> cl;
  std::vector<bool> used(static_cast<size_t>(ev.size()), false);
  for (Eigen::Index i = 0; i < ev.size(); ++i) {
    if (used[static_cast<size_t>(i)]) continue;
    Cluster c;
    c.members.push_back(ev(i));
    used[static_cast<size_t>(i)] = true;
    // Single-linkage growth: a Jordan block's computed eigenvalues form a ring around the true value.
    for (bool grew = true; grew;) {
      grew = false;
      for (Eigen::Index j = 0; j < ev.size(); ++j) {
        if (used[static_cast<size_t>(j)]) continue;
        for (const cplx& z : c.members)
          if (std::abs(ev(j) - z) <= radius) {
            c.members.push_back(ev(j));
            used[static_cast<size_t>(j)] = true;
            grew = true;
            break;
          }
      }
    }
    cplx sum = 0.0;
    for (const cplx& z : c.members) sum += z;
    c.mean = sum / static_cast<double>(c.members.size());
    cl.push_back(c);
  }
  return cl;
}

// Singular values of [A - lambda I, B] (n x (n + m)), ascending order of use: returns them descending.
VectorXd pbh_singular_values(const MatrixXd& A, const MatrixXd& B, cplx lambda) {
  const Eigen::Index n = A.rows(), m = B.cols();
  if (lambda.imag() == 0.0) {
    MatrixXd M(n, n + m);
    M.leftCols(n) = A - lambda.real() * MatrixXd::Identity(n, n);
    M.rightCols(m) = B;
    return Eigen::BDCSVD<MatrixXd>(M).singularValues();
  }
  MatrixXcd M(n, n + m);
  M.leftCols(n) = A.cast<cplx>() - lambda * MatrixXcd::Identity(n, n);
  M.rightCols(m) = B.cast<cplx>();
  return Eigen::BDCSVD<MatrixXcd>(M).singularValues();
}

double pbh_sigma_min(const MatrixXd& A, const MatrixXd& B, cplx lambda) {
  const VectorXd sv = pbh_singular_values(A, B, lambda);
  return sv(A.rows() - 1);
}

}  // namespace

PbhReport pbh(const MatrixXd& A_in, const MatrixXd& BC, Property p, const RankSettings& s) {
  const Pair pr = prepare(A_in, BC, p, s);
  const Eigen::Index n = pr.A.rows(), m = pr.B.cols();
  PbhReport out;
  RankReport& rep = out.summary;
  init_summary(rep, p, n, m, s, "pbh");
  MatrixXd AB(n, n + m);
  AB << pr.A, pr.B;
  const double normAB = safe_norm(AB), normA = pr.A.norm();
  // Eigenvalues closer than the rank tolerance of [A B] are indistinguishable too: with ||A|| tiny
  // against ||B|| they would otherwise form separate clusters whose deficiencies add up beyond n
  // (a negative rank for A = 1e-22 randn, B = randn).
  const double radius = std::max(s.cluster_rtol * normA, rep.rtol * normAB);
  Eigen::EigenSolver<MatrixXd> es(pr.A, false);
  const std::vector<Cluster> clusters = cluster_eigenvalues(es.eigenvalues(), radius);
  int rank_loss = 0;
  out.distance_upper_bound = kInf;
  out.stabilizable_ct = out.stabilizable_dt = true;
  for (const Cluster& c : clusters) {
    // Evaluate at the mean (accurate for a defective cluster) and at each member (accurate for a
    // semisimple one) and keep the most deficient.
    VectorXd best = pbh_singular_values(pr.A, pr.B, c.mean);
    cplx where = c.mean;
    if (c.members.size() > 1)
      for (const cplx& z : c.members) {
        VectorXd sv = pbh_singular_values(pr.A, pr.B, z);
        if (sv(n - 1) < best(n - 1)) {
          best = sv;
          where = z;
        }
      }
    PbhMode md;
    md.lambda = c.mean;
    md.multiplicity = static_cast<int>(c.members.size());
    md.sigma_min = best(n - 1) / normAB;
    for (Eigen::Index i = 0; i < n; ++i) {
      const double rel = best(i) / normAB;
      if (rel <= rep.rtol) ++md.deficiency;
    }
    md.deficiency = std::min(md.deficiency, md.multiplicity);  // at most the modes at this eigenvalue
    for (Eigen::Index i = 0; i < n - md.deficiency; ++i)
      rep.sigma_r = std::min(rep.sigma_r, best(i) / normAB);
    if (md.deficiency > 0) rep.sigma_next = std::max(rep.sigma_next, best(n - md.deficiency) / normAB);
    md.controllable = md.deficiency == 0;
    md.ct_stable = c.mean.real() < -radius;
    md.dt_stable = std::abs(c.mean) < 1.0 - radius;
    if (!md.controllable) {
      if (!md.ct_stable) out.stabilizable_ct = false;
      if (!md.dt_stable) out.stabilizable_dt = false;
    }
    out.distance_upper_bound = std::min(out.distance_upper_bound, best(n - 1));
    (void)where;
    RankReport local;
    local.n = 1;
    local.rank = md.controllable ? 1 : 0;
    local.rtol = rep.rtol;
    local.sigma_r = md.controllable ? md.sigma_min : kInf;
    local.sigma_next = md.controllable ? 0.0 : md.sigma_min;
    decide(local, s.fuzz, 0);
    md.verdict = local.verdict;
    rank_loss += md.deficiency;
    out.modes.push_back(md);
  }
  rep.rank = std::max(0, static_cast<int>(n) - rank_loss);
  const int subtol = count_subtolerance(AB, rep.rtol * normAB);
  decide(rep, s.fuzz, subtol);
  return out;
}

MatrixXd kalman_controllability_matrix(const MatrixXd& A, const MatrixXd& B) {
  const Pair pr = prepare(A, B, Property::controllability, RankSettings{});
  const Eigen::Index n = A.rows(), m = B.cols();
  MatrixXd K(n, n * m);
  K.leftCols(m) = B;
  for (Eigen::Index k = 1; k < n; ++k) K.middleCols(k * m, m) = A * K.middleCols((k - 1) * m, m);
  return K;
}

MatrixXd kalman_observability_matrix(const MatrixXd& A, const MatrixXd& C) {
  prepare(A, C, Property::observability, RankSettings{});
  const Eigen::Index n = A.rows(), p = C.rows();
  MatrixXd O(n * p, n);
  O.topRows(p) = C;
  for (Eigen::Index k = 1; k < n; ++k) O.middleRows(k * p, p) = O.middleRows((k - 1) * p, p) * A;
  return O;
}

RankReport kalman_rank(const MatrixXd& A, const MatrixXd& BC, Property p, const RankSettings& s) {
  const Pair pr = prepare(A, BC, p, s);
  const MatrixXd K = kalman_controllability_matrix(pr.A, pr.B);
  RankReport rep;
  rep.property = p;
  rep.n = static_cast<int>(pr.A.rows());
  rep.rtol = s.rtol > 0.0 ? s.rtol : static_cast<double>(std::max(K.rows(), K.cols())) * kEps;
  rep.method = "kalman-svd";
  const VectorXd sv = Eigen::BDCSVD<MatrixXd>(K).singularValues();
  const double smax = sv.size() > 0 && sv(0) > 0.0 ? sv(0) : 1.0;
  rep.sigma_r = kInf;
  for (Eigen::Index i = 0; i < sv.size(); ++i) {
    const double rel = sv(i) / smax;
    if (rel > rep.rtol) {
      ++rep.rank;
      rep.sigma_r = std::min(rep.sigma_r, rel);
    } else {
      rep.sigma_next = std::max(rep.sigma_next, rel);
    }
  }
  decide(rep, s.fuzz, 0);
  return rep;
}

DistanceReport distance_to_uncontrollability(const MatrixXd& A_in, const MatrixXd& BC, Property p,
                                             const RankSettings& s, int max_iter) {
  core::require(max_iter >= 0, "max_iter", "must be >= 0");
  const Pair pr = prepare(A_in, BC, p, s);
  const Eigen::Index n = pr.A.rows(), m = pr.B.cols();
  MatrixXd AB(n, n + m);
  AB << pr.A, pr.B;
  const double normAB = safe_norm(AB), normA = pr.A.norm();
  DistanceReport d;
  d.method =
      "min over eigenvalue clusters of sigma_min([A - lambda I, B]), then Nelder-Mead over "
      "(Re lambda, Im lambda) from each cluster";
  Eigen::EigenSolver<MatrixXd> es(pr.A, false);
  const std::vector<Cluster> clusters = cluster_eigenvalues(es.eigenvalues(), s.cluster_rtol * normA);
  auto f = [&](double x, double y) {
    ++d.evaluations;
    return pbh_sigma_min(pr.A, pr.B, cplx(x, y));
  };
  d.upper_bound = kInf;
  for (const Cluster& c : clusters) {
    const double v = f(c.mean.real(), c.mean.imag());
    if (v < d.upper_bound) {
      d.upper_bound = v;
      d.lambda_upper = c.mean;
    }
  }
  d.refined = d.upper_bound;
  d.lambda_refined = d.lambda_upper;
  for (const Cluster& c : clusters) {
    if (c.mean.imag() < 0.0) continue;  // real data: sigma_min(conj lambda) = sigma_min(lambda)
    // Nelder-Mead on a triangle around the eigenvalue.
    const double h = std::max(1e-2 * std::abs(c.mean), 1e-3 * std::max(normA, normAB * kEps));
    double px[3] = {c.mean.real(), c.mean.real() + h, c.mean.real()};
    double py[3] = {c.mean.imag(), c.mean.imag(), c.mean.imag() + h};
    double fv[3];
    for (int i = 0; i < 3; ++i) fv[i] = f(px[i], py[i]);
    for (int it = 0; it < max_iter; ++it) {
      int o[3] = {0, 1, 2};
      std::sort(o, o + 3, [&](int a, int b) { return fv[a] < fv[b]; });
      const int b = o[0], mid = o[1], w = o[2];
      const double size = std::abs(px[w] - px[b]) + std::abs(py[w] - py[b]);
      if (size <= 4.0 * kEps * std::max(1.0, std::abs(px[b]) + std::abs(py[b])) ||
          fv[w] - fv[b] <= kEps * normAB * 1e-3)
        break;
      const double cx = 0.5 * (px[b] + px[mid]), cy = 0.5 * (py[b] + py[mid]);
      const double rx = 2 * cx - px[w], ry = 2 * cy - py[w];
      const double fr = f(rx, ry);
      if (fr < fv[b]) {
        const double ex = 3 * cx - 2 * px[w], ey = 3 * cy - 2 * py[w];
        const double fe = f(ex, ey);
        if (fe < fr) {
          px[w] = ex, py[w] = ey, fv[w] = fe;
        } else {
          px[w] = rx, py[w] = ry, fv[w] = fr;
        }
      } else if (fr < fv[mid]) {
        px[w] = rx, py[w] = ry, fv[w] = fr;
      } else {
        const double kx = 0.5 * (cx + px[w]), ky = 0.5 * (cy + py[w]);
        const double fk = f(kx, ky);
        if (fk < fv[w]) {
          px[w] = kx, py[w] = ky, fv[w] = fk;
        } else {  // shrink towards the best vertex
          for (int i : {mid, w}) {
            px[i] = 0.5 * (px[i] + px[b]);
            py[i] = 0.5 * (py[i] + py[b]);
            fv[i] = f(px[i], py[i]);
          }
        }
      }
    }
    for (int i = 0; i < 3; ++i)
      if (fv[i] < d.refined) {
        d.refined = fv[i];
        d.lambda_refined = cplx(px[i], std::abs(py[i]));
      }
  }
  d.relative = d.refined / normAB;
  return d;
}

std::vector<LossRow> loss_table(const MatrixXd& A, const MatrixXd& BC, Property p, const RankSettings& s) {
  prepare(A, BC, p, s);  // validates before enumerating
  const bool ctrb = p == Property::controllability;
  const int k = static_cast<int>(ctrb ? BC.cols() : BC.rows());
  core::require(k <= 16, ctrb ? "B" : "C", "at most 16 channels for the loss table");
  std::vector<unsigned> masks;
  for (unsigned mask = 1; mask < (1u << k); ++mask) masks.push_back(mask);
  auto bits = [](unsigned v) { return __builtin_popcount(v); };
  auto lex_key = [&](unsigned v) {
    std::vector<int> idx;
    for (int i = 0; i < k; ++i)
      if (v & (1u << i)) idx.push_back(i);
    return idx;
  };
  std::sort(masks.begin(), masks.end(), [&](unsigned a, unsigned b) {
    if (bits(a) != bits(b)) return bits(a) > bits(b);
    return lex_key(a) < lex_key(b);
  });
  std::vector<LossRow> rows;
  for (unsigned mask : masks) {
    LossRow row;
    row.channels = lex_key(mask);
    MatrixXd sub = ctrb ? MatrixXd(A.rows(), row.channels.size()) : MatrixXd(row.channels.size(), A.cols());
    for (size_t i = 0; i < row.channels.size(); ++i) {
      if (ctrb)
        sub.col(static_cast<Eigen::Index>(i)) = BC.col(row.channels[i]);
      else
        sub.row(static_cast<Eigen::Index>(i)) = BC.row(row.channels[i]);
    }
    RankSettings ss = s;
    if (s.units) {  // keep the units of the kept channels only
      Eigen::VectorXd& ch = ctrb ? ss.units->input : ss.units->output;
      const Eigen::VectorXd all = ch;
      if (all.size() > 0) {
        ch.resize(static_cast<Eigen::Index>(row.channels.size()));
        for (size_t i = 0; i < row.channels.size(); ++i)
          ch(static_cast<Eigen::Index>(i)) = all(row.channels[i]);
      }
    }
    const StaircaseReport st = staircase(A, sub, p, ss);
    row.rank = st.summary.rank;
    row.verdict = st.summary.verdict;
    row.margin = st.summary.margin;
    RankSettings ks = ss;
    ks.rtol = 0.0;  // Kalman column: numpy's default tolerance, for comparison
    const RankReport kr = kalman_rank(A, sub, p, ks);
    row.kalman_rank = kr.rank;
    const Pair pr = prepare(A, sub, p, ss);
    const VectorXd sv = Eigen::BDCSVD<MatrixXd>(kalman_controllability_matrix(pr.A, pr.B)).singularValues();
    row.kalman_ratio = sv(0) > 0.0 ? sv(sv.size() - 1) / sv(0) : 0.0;
    rows.push_back(row);
  }
  return rows;
}

}  // namespace satgnc::analysis
