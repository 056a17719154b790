// SH-domain rotation against re-encoding the rotated directions, at every
// order; the listener's rotation; the SceneRotator and Encoder DSP units.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "../audio/alloc_counter.hpp"
#include "earshot/audio/ambisonics/encoder.hpp"
#include "earshot/audio/ambisonics/scene_rotator.hpp"
#include "earshot/audio/ambisonics/sh_rotation.hpp"
#include "earshot/audio/ambisonics/spherical_harmonics.hpp"

using namespace earshot;
using namespace earshot::ambisonics;

namespace {

constexpr double kPi = std::numbers::pi;

Quat random_quat(std::mt19937& rng) {
  std::normal_distribution<double> g;
  return *normalised(Quat{g(rng), g(rng), g(rng), g(rng)});
}

Vec3 random_direction(std::mt19937& rng) {
  std::normal_distribution<double> g;
  Vec3 v{g(rng), g(rng), g(rng)};
  const double n = norm(v);
  return {v[0] / n, v[1] / n, v[2] / n};
}

Vec3 apply(const Mat3& r, const Vec3& v) {
  return {r[0][0] * v[0] + r[0][1] * v[1] + r[0][2] * v[2], r[1][0] * v[0] + r[1][1] * v[1] + r[1][2] * v[2],
          r[2][0] * v[0] + r[2][1] * v[1] + r[2][2] * v[2]};
}

}  // namespace

TEST(ShRotation, RotatingEncodedWavesEqualsEncodingRotatedDirections) {
  std::mt19937 rng(11);
  for (int order = 0; order <= kMaxOrder; ++order) {
    const std::size_t C = channel_count(order);
    ShRotation rot(order);
    std::vector<double> y(C), ry(C), yr(C);
    double worst = 0.0;
    for (int trial = 0; trial < 40; ++trial) {
      const Mat3 r = matrix_from_quat(random_quat(rng));
      rot.set(r);
      for (int k = 0; k < 5; ++k) {
        const Vec3 d = random_direction(rng);
        real_sh(order, d, std::span<double>(y));
        rot.apply(y, ry);
        real_sh(order, apply(r, d), std::span<double>(yr));
        for (std::size_t c = 0; c < C; ++c) worst = std::max(worst, std::abs(ry[c] - yr[c]));
      }
    }
    EXPECT_LT(worst, 1e-11) << "order " << order;
  }
}

TEST(ShRotation, BlocksAreOrthogonalAndCompose) {
  std::mt19937 rng(12);
  const int N = 5;
  ShRotation a(N), b(N), ab(N);
  const Quat qa = random_quat(rng), qb = random_quat(rng);
  a.set(matrix_from_quat(qa));
  b.set(matrix_from_quat(qb));
  ab.set(matrix_from_quat(multiply(qa, qb)));
  for (int l = 0; l <= N; ++l) {
    const int s = 2 * l + 1;
    for (int i = -l; i <= l; ++i)
      for (int j = -l; j <= l; ++j) {
        double mtm = 0.0, prod = 0.0;
        for (int k = -l; k <= l; ++k) {
          mtm += a.at(l, k, i) * a.at(l, k, j);
          prod += a.at(l, i, k) * b.at(l, k, j);
        }
        EXPECT_NEAR(mtm, i == j ? 1.0 : 0.0, 1e-12);
        EXPECT_NEAR(prod, ab.at(l, i, j), 1e-12) << "degree " << l << " (" << s << "x" << s << ")";
      }
  }
}

TEST(ShRotation, ListenerTurningLeftHearsTheFrontOnTheRight) {
  // Yaw +90 deg turns the head left: a wave from the world's front then
  // comes from the head's right (ambiX -y), one from the left from ahead.
  const Mat3 r = field_rotation_for_listener(quat_from_ypr(kPi / 2, 0, 0));
  const Vec3 front = apply(r, {1, 0, 0}), left = apply(r, {0, 1, 0}), up = apply(r, {0, 0, 1});
  EXPECT_NEAR(front[1], -1.0, 1e-12);
  EXPECT_NEAR(left[0], 1.0, 1e-12);
  EXPECT_NEAR(up[2], 1.0, 1e-12);
  // Looking up (pitch +30 deg): the front sinks to -30 deg elevation.
  const Vec3 f2 = apply(field_rotation_for_listener(quat_from_ypr(0, kPi / 6, 0)), {1, 0, 0});
  EXPECT_NEAR(f2[2], -0.5, 1e-12);
  // Rolling right (up leans to +x): the left ear rises above the world's
  // left, which the head hears from -30 deg elevation.
  const Vec3 l2 = apply(field_rotation_for_listener(quat_from_ypr(0, 0, kPi / 6)), {0, 1, 0});
  EXPECT_NEAR(l2[2], -0.5, 1e-12);
}

TEST(SceneRotator, StillHeadAppliesTheRotationToEverySample) {
  const int N = 3;
  const std::size_t B = 64, C = channel_count(N);
  SceneRotator rot(N, B);
  const Quat q = quat_from_ypr(0.4, -0.2, 0.1);
  rot.update(q);
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> u(-1, 1);
  std::vector<float> in(C * B), out(C * B);
  for (float& v : in) v = u(rng);
  rot.process(in, out);
  ShRotation ref(N);
  ref.set(field_rotation_for_listener(q));
  std::vector<double> x(C), y(C);
  for (std::size_t n = 0; n < B; ++n) {
    for (std::size_t c = 0; c < C; ++c) x[c] = in[c * B + n];
    ref.apply(x, y);
    for (std::size_t c = 0; c < C; ++c) ASSERT_NEAR(out[c * B + n], y[c], 1e-5);
  }
}

TEST(SceneRotator, GlidesToTheNewOrientationByTheBlocksEnd) {
  const int N = 2;
  const std::size_t B = 32, C = channel_count(N);
  SceneRotator rot(N, B);
  rot.update(kIdentityQuat);
  std::vector<float> in(C * B), out(C * B);
  // A wave from ahead, held still; the head turns left by 10 degrees.
  std::vector<float> g(C);
  real_sh(N, Vec3{1, 0, 0}, std::span<float>(g));
  for (std::size_t c = 0; c < C; ++c) std::fill_n(in.begin() + static_cast<long>(c * B), B, g[c]);
  const Quat q = quat_from_ypr(10 * kPi / 180, 0, 0);
  rot.update(q);
  rot.process(in, out);
  std::vector<float> first(C), last(C);
  const auto heard = [&](double yaw) {
    std::vector<float> h(C);
    real_sh(N, Vec3{std::cos(yaw), std::sin(yaw), 0}, std::span<float>(h));
    return h;
  };
  const auto end = heard(-10 * kPi / 180);
  for (std::size_t c = 0; c < C; ++c) {
    EXPECT_NEAR(out[c * B + B - 1], end[c], 1e-5);                                     // the new pose at the end
    EXPECT_NEAR(out[c * B], g[c] + (end[c] - g[c]) / float(B), 1e-5);                 // one step in at the start
  }
  // The next block holds the new orientation throughout.
  rot.process(in, out);
  for (std::size_t c = 0; c < C; ++c) EXPECT_NEAR(out[c * B], end[c], 1e-5);
}

TEST(SceneRotator, LinearBlendOfNeighbouringMatricesStaysNearARotation) {
  // Between two orientations 1 degree apart (360 deg/s, 128 frames, 48 kHz)
  // the mid-block blend differs from the rotation half-way by this much.
  const int N = 5;
  ShRotation a(N), b(N), mid(N);
  const double step = 360.0 * 128.0 / 48000.0 * kPi / 180.0;
  a.set(field_rotation_for_listener(quat_from_ypr(0.3, 0.1, 0.0)));
  b.set(field_rotation_for_listener(quat_from_ypr(0.3 + step, 0.1, 0.0)));
  mid.set(field_rotation_for_listener(quat_from_ypr(0.3 + step / 2, 0.1, 0.0)));
  double worst = 0.0;
  for (int l = 0; l <= N; ++l)
    for (int i = -l; i <= l; ++i)
      for (int j = -l; j <= l; ++j)
        worst = std::max(worst, std::abs(0.5 * (a.at(l, i, j) + b.at(l, i, j)) - mid.at(l, i, j)));
  RecordProperty("worst_entry_error", std::to_string(worst));
  std::printf("mid-block blend vs rotation, order 5, 0.96 deg step: %.2e\n", worst);
  EXPECT_LT(worst, 1e-3);
}

TEST(SceneRotator, IgnoresBadQuaternionsAndNeverAllocates) {
  const int N = 5;
  const std::size_t B = 128, C = channel_count(N);
  SceneRotator rot(N, B);
  Encoder enc(N, B);
  std::vector<float> mono(B, 0.5f), bus(C * B, 0.0f), out(C * B);
  enc.update({1, 0, 0});
  rot.update(kIdentityQuat);
  {
    earshot::testing::AllocationProbe probe;
    for (int k = 0; k < 20; ++k) {
      enc.update({std::cos(0.1 * k), std::sin(0.1 * k), 0.2});
      std::fill(bus.begin(), bus.end(), 0.0f);
      enc.process(mono, bus);
      rot.update(quat_from_ypr(0.05 * k, 0.01 * k, 0));
      rot.process(bus, out);
    }
    rot.update({std::nan(""), 0, 0, 0});
    rot.update({0, 0, 0, 0});
    rot.process(bus, out);
    EXPECT_EQ(probe.count(), 0u);
    EXPECT_EQ(probe.lock_count(), 0u);
  }
  for (float v : out) ASSERT_TRUE(std::isfinite(v));
}

TEST(Encoder, RampsGainsAcrossTheBlock) {
  const std::size_t B = 16;
  Encoder enc(1, B);
  enc.update({1, 0, 0});  // ahead: W 1, X 1
  std::vector<float> mono(B, 1.0f), bus(4 * B, 0.0f);
  enc.process(mono, bus);
  EXPECT_FLOAT_EQ(bus[3 * B], 1.0f);
  enc.update({0, 1, 0}, 0.5f);  // left, half as loud
  std::fill(bus.begin(), bus.end(), 0.0f);
  enc.process(mono, bus);
  EXPECT_NEAR(bus[3 * B + B - 1], 0.0f, 1e-6);    // X at the end
  EXPECT_NEAR(bus[1 * B + B - 1], 0.5f, 1e-6);    // Y at the end
  EXPECT_NEAR(bus[3 * B], 1.0f - 1.0f / B, 1e-6);  // one step in
  EXPECT_NEAR(bus[0 * B + B / 2 - 1], 0.75f, 1e-6);  // W halfway from 1 to 0.5
}
