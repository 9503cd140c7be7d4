#include "calibrate_verb.hpp"

#include <CLI/CLI.hpp>

namespace volcomp::cli {

CLI::App* addCalibrateVerb(CLI::App& app, calibration::CalibrateOptions& options) {
  CLI::App* verb = app.add_subcommand(
      "calibrate",
      "Identify model parameters from measurements. TEMPLATE is a model file whose components say "
      "how to identify them ({\"identify\": \"constant\"}, {\"identify\": {\"basis\": "
      "\"polynomial\", \"degree\": N}}, {\"identify\": {\"basis\": \"table\", \"positions\": "
      "[...]}}), or a planar 2-DOF device file (\"format\": \"volcomp-planar2dof/1\", readings "
      "a,b,gx,gy); MEASUREMENTS is a CSV with header x,y,z,ex,ey,ez [,tx,ty,tz] [,ea,eb,ec] "
      "[,weight] [,direction] (mm, rad; a unit suffix such as ex_um is allowed). Writes an "
      "ordinary model file (with a \"calibration\" block: provenance, measured tools) and prints "
      "the parameters with their standard deviations, residuals per axis, prediction "
      "uncertainty, identified curves and the combinations the data cannot separate.");
  verb->add_option("template", options.templatePath, "Calibration template (volcomp-model/1)")
      ->required();
  verb->add_option("measurements", options.measurementsPath, "Measurement CSV")->required();
  verb->add_option("--out", options.outPath, "Identified model file to write")->required();
  verb->add_option("--report", options.reportPath, "Also write the report as JSON");
  verb->add_option("--method", options.method,
                   "auto (linear for 3-axis models, Levenberg-Marquardt for D-H chains and "
                   "robust losses), linear or lm")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "linear", "lm"}));
  verb->add_option("--loss", options.loss, "Robust loss: none, huber or cauchy (needs lm)")
      ->capture_default_str()
      ->check(CLI::IsMember({"none", "huber", "cauchy"}));
  verb->add_option("--loss-scale", options.lossScaleMm,
                   "Residual size (mm) beyond which the robust loss down-weights")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  verb->add_flag("--instrument-frame", options.identification.instrumentFrame,
                 "Also fit the instrument's frame (3 rotations + 3 translations, nuisance)");
  verb->add_option("--rank-tol", options.rankTolerance,
                   "Relative singular-value threshold of the rank decision (column-scaled)")
      ->capture_default_str()
      ->check(CLI::Range(1e-16, 0.5));
  verb->add_option("--angle-scale", options.identification.angleScaleMm,
                   "Weight of measured angular errors: mm of residual per rad")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  verb->add_option("--max-iterations", options.maxIterations, "Iteration limit")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  CLI::Option* validate = verb->add_option(
      "--validate", options.validatePath,
      "Held-out measurements (same CSV format): their residuals are reported beside the fit's");
  verb->add_option("--k-fold", options.folds,
                   "Cross-validate: K fits, each predicting the points of one fold (K >= 2)")
      ->check(CLI::Range(2, 1000))
      ->excludes(validate);
  CLI::Option* predict = verb->add_option(
      "--predict", options.predictPath,
      "Points x,y,z [,tx,ty,tz] [,direction] at which to predict the error with its standard "
      "uncertainty");
  CLI::Option* predictOut = verb->add_option(
      "--predict-out", options.predictOutPath,
      "CSV written for --predict: x,y,z,tx,ty,tz,ex,ey,ez,ux,uy,uz,k,determined (mm; u standard "
      "uncertainty, k the coverage factor of U = k u)");
  predict->needs(predictOut);
  predictOut->needs(predict);
  verb->add_option("--angle-unit", options.angleUnit, "Angles on screen: urad or arcsec")
      ->capture_default_str()
      ->check(CLI::IsMember({"urad", "arcsec"}));
  verb->add_flag("--force", options.force,
                 "Write the model even when the data identify fewer than half of the parameters");
  verb->footer(
      "Exit status: 0 done (unidentifiable parameters are reported, not an error); 2 bad "
      "arguments, a bad template/CSV, or data that identify fewer than half of the parameters "
      "without --force (one line on stderr: file, line or key, expectation).");
  return verb;
}

}  // namespace volcomp::cli
