#pragma once
// Test-local two-body propagator with STM: fixed-step RK4 on the 42-dim variational system.
// Independent of satgnc::propagation so the OD tests check the solvers, not the propagator.
#include <cmath>

#include "satgnc/od/propagator.hpp"

namespace satgnc::od::testing {

class Rk4StmPropagator final : public StmPropagator {
 public:
  explicit Rk4StmPropagator(double mu, double h = 1.0) : mu_(mu), h_(h) {}
  bool propagate(const Vec6& x0, const double* times, int n, Vec6* states, Mat6* stms) override {
    Vec6 x = x0;
    Mat6 phi = Mat6::Identity();
    double t = 0.0;
    for (int i = 0; i < n; ++i) {
      const double dt_total = times[i] - t;
      const int steps = std::max(1, static_cast<int>(std::ceil(std::abs(dt_total) / h_)));
      const double h = dt_total / steps;
      for (int k = 0; k < steps && dt_total != 0.0; ++k) step(x, phi, h);
      t = times[i];
      states[i] = x;
      stms[i] = phi;
    }
    return x.allFinite();
  }

 private:
  void deriv(const Vec6& x, const Mat6& phi, Vec6& dx, Mat6& dphi) const {
    const Vec3 r = x.head<3>();
    const double rn = r.norm(), r3 = rn * rn * rn;
    dx.head<3>() = x.tail<3>();
    dx.tail<3>() = -mu_ / r3 * r;
    Mat6 A = Mat6::Zero();
    A.topRightCorner<3, 3>() = Mat3::Identity();
    A.bottomLeftCorner<3, 3>() = mu_ / r3 * (3.0 * r * r.transpose() / (rn * rn) - Mat3::Identity());
    dphi = A * phi;
  }
  void step(Vec6& x, Mat6& phi, double h) const {
    Vec6 k1, k2, k3, k4;
    Mat6 p1, p2, p3, p4;
    deriv(x, phi, k1, p1);
    deriv(x + 0.5 * h * k1, phi + 0.5 * h * p1, k2, p2);
    deriv(x + 0.5 * h * k2, phi + 0.5 * h * p2, k3, p3);
    deriv(x + h * k3, phi + h * p3, k4, p4);
    x += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    phi += h / 6.0 * (p1 + 2.0 * p2 + 2.0 * p3 + p4);
  }
  double mu_, h_;
};

// The paper's scenario: Table 1 true state, Table 3 station position (rotating at Earth's rate).
inline Vec6 paper_truth() {
  Vec6 x;
  x << 5836.89070, 1265.61600, 3411.49600, 0.31460, 6.94010, -3.11250;
  return x;
}
inline Vec3 paper_station_r0() { return Vec3(5463.14996, 2139.12637, 2493.77850); }

}  // namespace satgnc::od::testing
