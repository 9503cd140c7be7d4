// The dense QR behind the linear identification (calibration/src/dense_qr.hpp): both builds (the
// baseline one every x86-64 CPU runs, and the AVX2 + FMA one) against Eigen's HouseholderQR as
// compiled here, and a whole identification with and without the AVX2 build.

#include <gtest/gtest.h>

#include <Eigen/QR>
#include <cmath>
#include <random>

// An internal header of the library (not installed), included by its path in the source tree.
#include "../../calibration/src/dense_qr.hpp"
#include "synthetic.hpp"
#include "volcomp/calibration/identification.hpp"
#include "volcomp/calibration/least_squares.hpp"
#include "volcomp/config/model_file.hpp"

namespace volcomp::calibration {
namespace {

using QrFunction = void (*)(double*, Eigen::Index, Eigen::Index, double*);
using ApplyFunction = void (*)(const double*, Eigen::Index, Eigen::Index, const double*, double*);

Eigen::MatrixXd randomMatrix(Eigen::Index rows, Eigen::Index columns, unsigned seed) {
  std::mt19937 generator(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd m(rows, columns);
  for (Eigen::Index j = 0; j < columns; ++j) {
    for (Eigen::Index i = 0; i < rows; ++i) m(i, j) = normal(generator);
  }
  return m;
}

// R and Q^T x of `qr`/`apply` against Eigen's HouseholderQR of the same matrix, relative to |A|.
void expectSameAsEigen(const Eigen::MatrixXd& a, QrFunction qr, ApplyFunction apply) {
  const Eigen::Index m = a.rows(), n = a.cols();
  const Eigen::HouseholderQR<Eigen::MatrixXd> reference(a);
  Eigen::MatrixXd factors = a;
  Eigen::VectorXd tau(n);
  qr(factors.data(), m, n, tau.data());
  const double scale = a.norm();
  const Eigen::MatrixXd r = factors.topRows(n).triangularView<Eigen::Upper>();
  const Eigen::MatrixXd rReference = reference.matrixQR().topRows(n).triangularView<Eigen::Upper>();
  EXPECT_LE((r - rReference).norm(), 1e-13 * scale);
  // Q R reproduces A, whatever the reflectors' signs.
  Eigen::MatrixXd rebuilt = Eigen::MatrixXd::Zero(m, n);
  rebuilt.topRows(n) = r;
  rebuilt.applyOnTheLeft(reference.householderQ());
  EXPECT_LE((rebuilt - a).norm(), 1e-13 * scale);

  const Eigen::VectorXd x = randomMatrix(m, 1, 99).col(0);
  Eigen::VectorXd qtx = x;
  apply(factors.data(), m, n, tau.data(), qtx.data());
  const Eigen::VectorXd qtxReference = reference.householderQ().adjoint() * x;
  EXPECT_LE((qtx - qtxReference).norm(), 1e-13 * x.norm());
}

TEST(DenseQr, BaselineBuildIsEigensHouseholderQr) {
  // Tall, with a dependent column (rank deficient, as identification matrices often are), and
  // wide enough for Eigen's blocked path (more than 48 columns).
  Eigen::MatrixXd a = randomMatrix(700, 90, 1);
  a.col(7) = 2.0 * a.col(3) - a.col(5);
  expectSameAsEigen(a, detail::baseline::householderQr, detail::baseline::applyQTranspose);
  expectSameAsEigen(randomMatrix(40, 40, 2), detail::baseline::householderQr,
                    detail::baseline::applyQTranspose);
}

TEST(DenseQr, Avx2BuildIsEigensHouseholderQr) {
  if (!detail::denseKernelsUseAvx2()) {
    // This CPU runs the baseline build only; the test above covers what it runs.
    EXPECT_FALSE(detail::denseKernelsUseAvx2());
    return;
  }
  Eigen::MatrixXd a = randomMatrix(700, 90, 1);
  a.col(7) = 2.0 * a.col(3) - a.col(5);
  expectSameAsEigen(a, detail::avx2::householderQr, detail::avx2::applyQTranspose);
  expectSameAsEigen(randomMatrix(40, 40, 2), detail::avx2::householderQr,
                    detail::avx2::applyQTranspose);
}

TEST(DenseQr, IdentificationIsTheSameWithoutAvx2) {
  // A whole linear identification with the baseline kernels (as on a CPU without AVX2) and with
  // the kernels the CPU allows: same rank, same null space, parameters and sigmas equal to
  // rounding.
  const std::string examples = VOLCOMP_EXAMPLES_DIR;
  testing::SyntheticOptions options;
  options.tools = {Eigen::Vector3d(0, 0, 120), Eigen::Vector3d(0, 0, 220),
                   Eigen::Vector3d(100, 0, 120)};
  options.noiseMm = 1e-3;
  const MeasurementSet data =
      testing::simulate(std::get<model::MachineModelSpec>(
                            config::loadModelFile(examples + "/vmc-xyfz-21-true.json").spec),
                        options);
  config::ParseOptions parse;
  parse.allowIdentify = true;
  const auto problem = makeIdentificationProblem(
      config::loadModelFile(examples + "/vmc-xyfz-21-template.json", parse), data);
  detail::allowAvx2DenseKernels(false);
  const FitResult baseline = solve(*problem, problem->startVector());
  detail::allowAvx2DenseKernels(true);
  const FitResult dispatched = solve(*problem, problem->startVector());
  ASSERT_EQ(baseline.statistics.rank, dispatched.statistics.rank);
  ASSERT_EQ(baseline.statistics.identifiable, dispatched.statistics.identifiable);
  for (Eigen::Index j = 0; j < baseline.parameters.size(); ++j) {
    const double sigma = dispatched.statistics.standardDeviation(j);
    const double tolerance = std::isfinite(sigma) ? 1e-6 * sigma : 1e-9;
    EXPECT_NEAR(baseline.parameters(j), dispatched.parameters(j), tolerance) << j;
    if (std::isfinite(sigma)) {
      EXPECT_NEAR(baseline.statistics.standardDeviation(j), sigma, 1e-9 * sigma) << j;
    }
  }
}

}  // namespace
}  // namespace volcomp::calibration
