// Fixed as an Eigen scalar: fixed-size products, sums and coefficient-wise operations agree with the double
// computation on the same (quantised) values within the rounding bound, and saturate instead of wrapping.
#include <cmath>
#include <cstdint>

#include <Eigen/Core>

#include "rockwatch/core/fixed_point.hpp"
#include "rockwatch/core/fixed_point_eigen.hpp"

#include <CppUTest/TestHarness.h>

// The file's own scope in a unity build (tests/CMakeLists.txt): its helpers' names recur in other files of the suite.
namespace unity_test_fixed_point_eigen {

using namespace rockwatch::core;

namespace {

using Q = Fixed<7, 24>;
using Mat23 = Eigen::Matrix<Q, 2, 3>;
using Vec3 = Eigen::Matrix<Q, 3, 1>;
using Vec2 = Eigen::Matrix<Q, 2, 1>;
using Mat33 = Eigen::Matrix<Q, 3, 3>;
using Q31_0 = Fixed<31, 0>;
using Q0_31 = Fixed<0, 31>;

// Half a Q7.24 step: the error of one same-format product.
const double kHalfStep = 0.5 * Q::resolution_value();

// SplitMix64 with a fixed seed (the same values on every platform).
struct SplitMix64 {
  std::uint64_t state;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  // Uniform in [−limit, limit), quantised to Q7.24.
  Q value(double limit) { return Q(limit * (2.0 * std::ldexp(double(next() >> 11), -53) - 1.0)); }
};

template <int R, int C>
Eigen::Matrix<Q, R, C> random_matrix(SplitMix64& rng, double limit) {
  Eigen::Matrix<Q, R, C> m;
  for (int i = 0; i < R; ++i) {
    for (int j = 0; j < C; ++j) m(i, j) = rng.value(limit);
  }
  return m;
}

template <int R, int C>
Eigen::Matrix<double, R, C> to_double(const Eigen::Matrix<Q, R, C>& m) {
  return m.unaryExpr([](Q v) { return v.to_double(); });
}

constexpr int kTrials = 2000;

}  // namespace

TEST_GROUP(FixedPointEigen){};

TEST(FixedPointEigen, NumTraitsDescribeTheFormat) {
  using Traits = Eigen::NumTraits<Q>;
  CHECK(Traits::epsilon() == Q::resolution());
  CHECK(Traits::highest() == Q::highest());
  CHECK(Traits::lowest() == Q::lowest());
  CHECK(Traits::dummy_precision() == Q::from_raw(128));
  CHECK(Eigen::NumTraits<Q31_0>::dummy_precision() == Q31_0(1));
  LONGS_EQUAL(7, Traits::digits10());
  LONGS_EQUAL(9, Eigen::NumTraits<Q0_31>::digits10());
  LONGS_EQUAL(0, Traits::IsComplex);
  LONGS_EQUAL(0, Traits::IsInteger);
  LONGS_EQUAL(1, Traits::IsSigned);
  LONGS_EQUAL(0, Traits::RequireInitialization);
}

TEST(FixedPointEigen, MatrixVectorProductAgreesWithDoubleWithinTheRoundingBound) {
  // Each coefficient is a 3-term inner product: three roundings, exact saturating sums (no saturation here:
  // |entries| < 2 and < 20 keep every partial sum below 120).
  SplitMix64 rng{101};
  for (int t = 0; t < kTrials; ++t) {
    const Mat23 a = random_matrix<2, 3>(rng, 2.0);
    const Vec3 x = random_matrix<3, 1>(rng, 20.0);
    const Vec2 y = a * x;
    const Eigen::Vector2d expected = to_double(a) * to_double(x);
    for (int i = 0; i < 2; ++i) DOUBLES_EQUAL(expected(i), y(i).to_double(), 3.0 * kHalfStep);
  }
}

TEST(FixedPointEigen, MatrixProductsSumsAndReductionsAgreeWithDouble) {
  SplitMix64 rng{102};
  for (int t = 0; t < kTrials; ++t) {
    const Mat33 a = random_matrix<3, 3>(rng, 3.0);
    const Mat33 b = random_matrix<3, 3>(rng, 3.0);
    const Vec3 u = random_matrix<3, 1>(rng, 5.0);
    const Vec3 v = random_matrix<3, 1>(rng, 5.0);
    const Eigen::Matrix3d ad = to_double(a);
    const Eigen::Matrix3d bd = to_double(b);
    const Eigen::Vector3d ud = to_double(u);
    const Eigen::Vector3d vd = to_double(v);
    // Products: n roundings per coefficient.
    const Mat33 ab = a * b;
    const Mat33 atb = a.transpose() * b;
    const Eigen::Matrix3d abd = ad * bd;
    const Eigen::Matrix3d atbd = ad.transpose() * bd;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        DOUBLES_EQUAL(abd(i, j), ab(i, j).to_double(), 3.0 * kHalfStep);
        DOUBLES_EQUAL(atbd(i, j), atb(i, j).to_double(), 3.0 * kHalfStep);
      }
    }
    DOUBLES_EQUAL(ud.dot(vd), u.dot(v).to_double(), 3.0 * kHalfStep);
    DOUBLES_EQUAL(ud.squaredNorm(), u.squaredNorm().to_double(), 3.0 * kHalfStep);
    // Sums and differences are exact.
    DOUBLES_EQUAL(ad.sum(), a.sum().to_double(), 0.0);
    CHECK(to_double(Mat33(a + b)) == ad + bd);
    CHECK(to_double(Mat33(a - b)) == ad - bd);
    CHECK(to_double(Mat33(-a)) == -ad);
    // Coefficient-wise: one rounding per product; abs, max, min exact.
    const Mat33 prod = a.cwiseProduct(b);
    const Mat33 scaled = a * Q(0.375);
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        DOUBLES_EQUAL(ad(i, j) * bd(i, j), prod(i, j).to_double(), kHalfStep);
        DOUBLES_EQUAL(ad(i, j) * 0.375, scaled(i, j).to_double(), kHalfStep);
      }
    }
    CHECK(to_double(Mat33(a.cwiseAbs())) == ad.cwiseAbs());
    CHECK(to_double(Mat33(a.cwiseMax(b))) == ad.cwiseMax(bd));
    CHECK(to_double(Mat33(a.cwiseMin(b))) == ad.cwiseMin(bd));
    DOUBLES_EQUAL(ad.maxCoeff(), a.maxCoeff().to_double(), 0.0);
    DOUBLES_EQUAL(ad.minCoeff(), a.minCoeff().to_double(), 0.0);
    DOUBLES_EQUAL(ad.cwiseAbs().sum(), a.cwiseAbs().sum().to_double(), 0.0);
  }
}

TEST(FixedPointEigen, ConstantsAndInPlaceOperations) {
  const Mat33 identity = Mat33::Identity();
  CHECK(to_double(identity) == Eigen::Matrix3d::Identity());
  CHECK(to_double(Mat33(Mat33::Zero())) == Eigen::Matrix3d::Zero());
  CHECK(to_double(Mat33(Mat33::Constant(Q(1.5)))) == Eigen::Matrix3d::Constant(1.5));
  Vec3 v(Q(1), Q(-2), Q(0.5));
  const Mat33 a = Mat33::Constant(Q(0.25));
  CHECK(Vec3(identity * v) == v);
  v += Vec3::Constant(Q(1));
  v *= Q(2);
  CHECK(to_double(v) == Eigen::Vector3d(4.0, -2.0, 3.0));
  CHECK(to_double(Vec3(a * v)) == Eigen::Vector3d::Constant(1.25));
  CHECK(v.isApprox(v));
  CHECK(!v.isApprox(Vec3(Vec3::Constant(Q(1)))));
  CHECK(Vec3(v - v).isZero());
  // Reductions that divide or multiply: mean = sum / Q(size), prod one rounding per factor.
  CHECK(v.mean() == Q(5) / Q(3));
  CHECK(v.prod() == Q(-24));
}

TEST(FixedPointEigen, SaturationPropagatesInsteadOfWrapping) {
  // Every product and partial sum here exceeds Q7.24's ±128: with wrapping int32 arithmetic the results would
  // change sign; saturating arithmetic pins them at the end of the range with the true sign.
  const Mat23 a = Mat23::Constant(Q(100));
  const Vec3 x = Vec3::Constant(Q(100));
  const Vec2 y = a * x;
  CHECK(y(0) == Q::highest());
  CHECK(y(1) == Q::highest());
  const Vec2 y_negative = a * Vec3(-x);
  CHECK(y_negative(0) == Q::lowest());
  CHECK(y_negative(1) == Q::lowest());
  // Sums without any product overflow: 3 · 100 = 300.
  const Vec3 hundreds = Vec3::Constant(Q(100));
  CHECK(hundreds.sum() == Q::highest());
  CHECK(Vec3(-hundreds).sum() == Q::lowest());
  CHECK(hundreds.dot(Vec3::Constant(Q(1))) == Q::highest());
  CHECK(hundreds.squaredNorm() == Q::highest());
  CHECK(Vec3(hundreds + hundreds) == Vec3::Constant(Q::highest()));
  CHECK(Vec3(-hundreds - hundreds) == Vec3::Constant(Q::lowest()));
  CHECK(Mat33(Mat33::Constant(Q::lowest()).cwiseAbs()) == Mat33::Constant(Q::highest()));
}

}  // namespace unity_test_fixed_point_eigen
