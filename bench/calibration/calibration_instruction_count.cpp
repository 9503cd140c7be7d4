// Fixed work for callgrind instruction counts of the 21-component identification (Google
// Benchmark's run length depends on time, so its instruction totals do not compare between
// runs). Cost of one operation, independent of the setup (building the case, simulating data):
//   valgrind --tool=callgrind ./calibration_instruction_count solve 1   (total I1)
//   valgrind --tool=callgrind ./calibration_instruction_count solve 2   (total I2)
//   I2 - I1
// Operations: solve (identification with covariance, correlation, null space: what
// bench_calibration times), jacobian (the sensitivity matrix alone); planar (the planar 2-DOF
// device's fit with its statistics, BM_PlanarDeviceFit) and planar-anchor (Eigen's MINPACK port
// with its covariance on the same residuals, BM_PlanarDeviceFitAnchorEigenMinpack), dh (the D-H
// chain fit, BM_DhChainFit).

#include <cstdio>
#include <cstdlib>
#include <string>

#include "dh_case.hpp"
#include "planar_case.hpp"
#include "vmc_case.hpp"

int main(int argc, char** argv) {
  using namespace volcomp;
  const std::string operation = argc > 1 ? argv[1] : "";
  const int repeats = argc > 2 ? std::atoi(argv[2]) : 0;
  if ((operation != "solve" && operation != "jacobian" && operation != "planar" &&
       operation != "planar-anchor" && operation != "dh") ||
      repeats < 1) {
    std::fprintf(stderr,
                 "usage: calibration_instruction_count solve|jacobian|planar|planar-anchor|dh "
                 "REPEATS\n");
    return 2;
  }
  if (operation == "dh") {
    const auto& dh = *bench::dhCase().problem;
    calibration::SolveOptions options;
    options.method = calibration::Method::LevenbergMarquardt;
    double sum = 0.0;
    for (int k = 0; k < repeats; ++k) {
      const calibration::FitResult fit = calibration::solve(dh, dh.startVector(), options);
      sum += fit.iterations + fit.statistics.standardDeviation(0);
    }
    std::printf("%.17g\n", sum);
    return 0;
  }
  if (operation == "planar" || operation == "planar-anchor") {
    const calibration::Planar2DofParameters startValues = bench::planarStart();
    const calibration::Planar2DofProblem planar({}, bench::planarData(), 0,
                                                calibration::kPaperFreeParameters, startValues);
    const Eigen::VectorXd start = planar.freeVector(startValues);
    calibration::SolveOptions options;
    options.method = calibration::Method::LevenbergMarquardt;
    double sum = 0.0;
    for (int k = 0; k < repeats; ++k) {
      if (operation == "planar") {
        const calibration::FitResult fit = calibration::solve(planar, start, options);
        sum += fit.iterations + fit.statistics.standardDeviation(0);
      } else {
        const bench::AnchorFit fit = bench::anchorFit(planar, start);
        sum += fit.iterations + fit.standardDeviation(0);
      }
    }
    std::printf("%.17g\n", sum);
    return 0;
  }
  const bench::VmcCase& c = bench::vmcCase();
  const auto problem = calibration::makeIdentificationProblem(c.document, c.data);
  const Eigen::VectorXd start = problem->startVector();
  // Printed so that no run can be optimised away.
  double sum = 0.0;
  for (int k = 0; k < repeats; ++k) {
    if (operation != "jacobian") {
      const calibration::FitResult fit = calibration::solve(*problem, start);
      sum += fit.statistics.rank + fit.statistics.covariance(0, 0);
    } else {
      Eigen::MatrixXd jacobian;
      problem->jacobian(start, jacobian);
      sum += jacobian(0, 0);
    }
  }
  std::printf("%.17g\n", sum);
  return 0;
}
