// Lambda Twist P3P, written from the paper (Persson & Nordberg, ECCV 2018).
//
// With unknown depths L = (l1, l2, l3) along unit bearings y_i, the three
// distance constraints |l_i y_i - l_j y_j|^2 = a_ij are quadratic forms
// L^T M_ij L = a_ij. Eliminating the right-hand sides gives two homogeneous
// conics D1 = a23 M12 - a12 M23 and D2 = a23 M13 - a13 M23 whose common
// points hold every solution. A degenerate member D0 = D1 + g D2 of their
// pencil (g a real root of the cubic det(D1 + g D2) = 0) is a pair of planes
// through the origin; intersecting each plane with D2 gives at most two
// directions each, scaled to satisfy |l1 y1 - l2 y2|^2 = a12. A few
// Gauss-Newton steps polish the depths; the pose follows from the two
// triangles.
#include "earshot/tracker/solve/p3p.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace earshot::tracker {
namespace {

double det_cols(const Vec3& a, const Vec3& b, const Vec3& c) { return a.dot(b.cross(c)); }

/// Real roots of c3 g^3 + c2 g^2 + c1 g + c0 (c3 != 0), each polished by Newton.
int cubic_real_roots(double c3, double c2, double c1, double c0, std::array<double, 3>& roots) {
  const double a = c2 / c3, b = c1 / c3, c = c0 / c3;
  const double q = (a * a - 3.0 * b) / 9.0;
  const double r = (2.0 * a * a * a - 9.0 * a * b + 27.0 * c) / 54.0;
  int n = 0;
  if (r * r < q * q * q) {
    const double theta = std::acos(std::clamp(r / std::sqrt(q * q * q), -1.0, 1.0));
    const double sq = -2.0 * std::sqrt(q);
    roots[0] = sq * std::cos(theta / 3.0) - a / 3.0;
    roots[1] = sq * std::cos((theta + 2.0 * M_PI) / 3.0) - a / 3.0;
    roots[2] = sq * std::cos((theta - 2.0 * M_PI) / 3.0) - a / 3.0;
    n = 3;
  } else {
    double A = -std::cbrt(std::abs(r) + std::sqrt(r * r - q * q * q));
    if (r < 0.0) A = -A;
    const double B = (A != 0.0) ? q / A : 0.0;
    roots[0] = (A + B) - a / 3.0;
    n = 1;
  }
  for (int i = 0; i < n; ++i) {
    double g = roots[static_cast<size_t>(i)];
    for (int it = 0; it < 8; ++it) {
      const double f = ((g + a) * g + b) * g + c;
      const double df = (3.0 * g + 2.0 * a) * g + b;
      if (df == 0.0) break;
      const double step = f / df;
      g -= step;
      if (std::abs(step) <= 1e-15 * (1.0 + std::abs(g))) break;
    }
    roots[static_cast<size_t>(i)] = g;
  }
  return n;
}

}  // namespace

P3PSolutions p3p_lambda_twist(const std::array<Vec3, 3>& y, const std::array<Vec3, 3>& x) {
  P3PSolutions out;
  const double b12 = y[0].dot(y[1]), b13 = y[0].dot(y[2]), b23 = y[1].dot(y[2]);
  const double a12 = (x[0] - x[1]).squaredNorm();
  const double a13 = (x[0] - x[2]).squaredNorm();
  const double a23 = (x[1] - x[2]).squaredNorm();
  const Vec3 d12 = x[0] - x[1], d13 = x[0] - x[2];
  const Vec3 nx = d12.cross(d13);
  if (nx.squaredNorm() < 1e-12 * a12 * a13) return out;  // collinear points

  Mat3 M12, M13, M23;
  M12 << 1, -b12, 0, -b12, 1, 0, 0, 0, 0;
  M13 << 1, 0, -b13, 0, 0, 0, -b13, 0, 1;
  M23 << 0, 0, 0, 0, 1, -b23, 0, -b23, 1;
  const Mat3 D1 = a23 * M12 - a12 * M23;
  const Mat3 D2 = a23 * M13 - a13 * M23;

  // det(D1 + g D2) = c3 g^3 + c2 g^2 + c1 g + c0, expanded column by column.
  const Vec3 p0 = D1.col(0), p1 = D1.col(1), p2 = D1.col(2);
  const Vec3 q0 = D2.col(0), q1 = D2.col(1), q2 = D2.col(2);
  const double c0 = det_cols(p0, p1, p2);
  const double c1 = det_cols(q0, p1, p2) + det_cols(p0, q1, p2) + det_cols(p0, p1, q2);
  const double c2 = det_cols(p0, q1, q2) + det_cols(q0, p1, q2) + det_cols(q0, q1, p2);
  const double c3 = det_cols(q0, q1, q2);

  std::array<double, 3> roots{};
  int nroots = 0;
  if (std::abs(c3) > 1e-14 * (std::abs(c0) + std::abs(c1) + std::abs(c2) + 1e-300)) {
    nroots = cubic_real_roots(c3, c2, c1, c0, roots);
  } else if (std::abs(c2) > 0.0) {  // the pencil's cubic lost its top term
    const double disc = c1 * c1 - 4.0 * c2 * c0;
    if (disc >= 0.0) {
      roots[0] = (-c1 + std::sqrt(disc)) / (2.0 * c2);
      roots[1] = (-c1 - std::sqrt(disc)) / (2.0 * c2);
      nroots = 2;
    }
  }

  // Pick the root whose degenerate conic is most clearly a pair of real planes.
  double best_quality = 0.0;
  Eigen::SelfAdjointEigenSolver<Mat3> eig;
  Vec3 e_pos = Vec3::Zero(), e_neg = Vec3::Zero();
  double s_pos = 0.0, s_neg = 0.0;
  for (int i = 0; i < nroots; ++i) {
    const Mat3 D0 = D1 + roots[static_cast<size_t>(i)] * D2;
    eig.compute(D0);
    const Vec3 ev = eig.eigenvalues();  // ascending
    const double scale = ev.cwiseAbs().maxCoeff();
    if (scale <= 0.0) continue;
    // The eigenvalue nearest zero is the degenerate one; the other two must
    // have opposite signs for the planes to be real.
    int zero = 0;
    for (int k = 1; k < 3; ++k)
      if (std::abs(ev[k]) < std::abs(ev[zero])) zero = k;
    const int ia = (zero == 0) ? 1 : 0;
    const int ib = (zero == 2) ? 1 : 2;
    if (ev[ia] * ev[ib] >= 0.0) continue;
    const double quality = std::min(std::abs(ev[ia]), std::abs(ev[ib])) / scale;
    if (quality > best_quality) {
      best_quality = quality;
      const int ip = ev[ia] > 0.0 ? ia : ib, in = ev[ia] > 0.0 ? ib : ia;
      e_pos = eig.eigenvectors().col(ip);
      e_neg = eig.eigenvectors().col(in);
      s_pos = ev[ip];
      s_neg = ev[in];
    }
  }
  if (best_quality <= 0.0) return out;

  const double s = std::sqrt(-s_neg / s_pos);
  const Mat3 X = (Mat3() << d12, d13, nx).finished();
  const Mat3 Xinv = X.inverse();

  for (double sign : {1.0, -1.0}) {
    const Vec3 w = (e_pos - sign * s * e_neg).normalized();  // plane w . L = 0
    // Orthonormal basis (u, v) of the plane.
    Vec3 u = w.unitOrthogonal();
    const Vec3 v = w.cross(u);
    const double A = u.dot(D2 * u), B = u.dot(D2 * v), C = v.dot(D2 * v);
    const double disc = B * B - A * C;
    if (disc < 0.0) continue;
    const double sq = std::sqrt(disc);
    std::array<Vec3, 2> dirs;
    if (std::abs(A) >= std::abs(C)) {
      if (A == 0.0) continue;
      dirs = {((-B + sq) / A) * u + v, ((-B - sq) / A) * u + v};
    } else {
      dirs = {u + ((-B + sq) / C) * v, u + ((-B - sq) / C) * v};
    }
    for (const Vec3& dir : dirs) {
      const double m = dir.dot(M12 * dir);
      if (!(m > 1e-300)) continue;
      Vec3 L = std::sqrt(a12 / m) * dir;
      if (L.sum() < 0.0) L = -L;
      if (L.minCoeff() <= 0.0) continue;
      // Gauss-Newton polish of the three distance equations.
      for (int it = 0; it < 5; ++it) {
        const Vec3 r(L.dot(M12 * L) - a12, L.dot(M13 * L) - a13, L.dot(M23 * L) - a23);
        Mat3 J;
        J.row(0) = 2.0 * (M12 * L).transpose();
        J.row(1) = 2.0 * (M13 * L).transpose();
        J.row(2) = 2.0 * (M23 * L).transpose();
        const double detJ = J.determinant();
        if (std::abs(detJ) < 1e-300) break;
        const Vec3 step = J.inverse() * r;
        const Vec3 Ln = L - step;
        const Vec3 rn(Ln.dot(M12 * Ln) - a12, Ln.dot(M13 * Ln) - a13, Ln.dot(M23 * Ln) - a23);
        if (rn.squaredNorm() >= r.squaredNorm()) break;
        L = Ln;
      }
      if (L.minCoeff() <= 0.0 || !L.allFinite()) continue;
      const Vec3 Y1 = L[0] * y[0] - L[1] * y[1];
      const Vec3 Y2 = L[0] * y[0] - L[2] * y[2];
      Mat3 Y;
      Y << Y1, Y2, Y1.cross(Y2);
      Mat3 R = Y * Xinv;
      if ((R.transpose() * R - Mat3::Identity()).cwiseAbs().maxCoeff() > 1e-9) R = nearest_rotation(R);
      const Vec3 t = L[0] * y[0] - R * x[0];
      if (!R.allFinite() || !t.allFinite()) continue;
      // Skip an exact duplicate (a double root reached from both planes).
      bool dup = false;
      for (int k = 0; k < out.count; ++k)
        dup = dup || ((out.poses[static_cast<size_t>(k)].R - R).cwiseAbs().maxCoeff() < 1e-10 &&
                      (out.poses[static_cast<size_t>(k)].t - t).norm() < 1e-9 * (1.0 + t.norm()));
      if (!dup && out.count < 4) out.poses[static_cast<size_t>(out.count++)] = {R, t};
    }
  }
  return out;
}

}  // namespace earshot::tracker
