// SPDX-License-Identifier: MIT
// A Monte Carlo unit with the controller on (work.hpp ClosedLoopConfig): the closed-loop
// experiment of its seed, identified two-stage; the test-length prefixes identified from
// their own rows alone; the controller's model perturbed per seed; a model the controller
// cannot run the plant on refused naming the seed.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "host/design/table.hpp"
#include "host/identify/closed_loop.hpp"
#include "host/montecarlo/records.hpp"
#include "host/montecarlo/summary.hpp"
#include "host/montecarlo/unit.hpp"
#include "host/simulate/closed_loop.hpp"
#include "sim/control/controller_file.hpp"
#include "sim/control/integral_controllability.hpp"
#include "sim/control/make_controller.hpp"
#include "sim/library/library.hpp"
#include "sim/library/perturb.hpp"
#include "sim/plants/plant.hpp"

namespace mc = excite::host::montecarlo;
namespace host = excite::host;
namespace sim = excite::sim;

namespace {

const std::string kPi = std::string(EXCITE_CONTROL_EXAMPLES) + "/woodberry2x2.pi.toml";
const std::string kDmc = std::string(EXCITE_CONTROL_EXAMPLES) + "/alatiqi4x4.dmc.toml";

// One seed of prbsUnc on `plant` under `controller`, noise 5e-4, the 50 % grid; normalised.
mc::Config prbs_unc(const std::string& plant, const std::string& controller, std::uint64_t seed,
                    double controller_perturb = 0.0, const std::string& excitation = "setpoint") {
  mc::Config c;
  c.plant = plant;
  c.designs = {"prbsUnc"};
  c.seeds = 1;
  c.first_seed = seed;
  c.noise_variance = 5e-4;
  c.length_step_percent = 50;
  c.closed_loop.controller = controller;
  c.closed_loop.excitation = excitation;
  c.closed_loop.model_perturb_percent = controller_perturb;
  mc::normalise(c);
  return c;
}

// woodberry2x2 under the example PI, prbsUnc as an MV dither (a PI file has no CV limits).
mc::Config pi_dither(double controller_perturb = 0.0) {
  return prbs_unc("woodberry2x2", kPi, 3, controller_perturb, "mv");
}

}  // namespace

TEST(ClosedLoopUnit, IsTheClosedLoopRunOfItsSeedIdentifiedTwoStage) {
  const mc::Config config = pi_dither();
  const auto prepared = mc::prepare(config, 1);
  const mc::UnitResult u = mc::run_unit(*prepared, {0, 3, 0});

  // The same run made by hand: simulate_closed_loop with seed 100·3 + prbsUnc's number,
  // identify_closed_loop on it.
  const auto file = sim::control::load_controller_file(kPi);
  const auto plant = sim::make_plant("woodberry2x2");
  const auto model = sim::control::load_model(file);
  const Eigen::MatrixXd g0 = plant->static_gain();
  const auto controller = sim::control::make_controller(file, *model, &g0);
  host::ClosedLoopOptions loop;
  loop.excitation = excite::runlog::Excitation::mv;
  host::set_controller(loop, file, "woodberry2x2.pi.toml");
  host::SimulationOptions noise;
  noise.noise_variance = 5e-4;
  noise.seed = 300 + static_cast<std::uint64_t>(prepared->presets[0].number);
  const excite::plan::Plan& plan = *prepared->designs[0].plan;
  const host::SimulatedRun run =
      host::simulate_closed_loop(host::make_table(plan.recipe), "prbsUnc",
                                 plan.meta.sample_time_min, *plant, *controller, loop, noise);
  host::IdentifyOptions options;
  options.threads = 1;
  options.max_time_constant_min = prepared->max_time_constant_min;
  const host::ClosedLoopIdentification by_hand =
      host::identify_closed_loop(run.du, run.closed_loop->r, run.dy, run.sample_time_min,
                                 host::SampleLayout::whole(run.du.rows()), options);

  ASSERT_TRUE(by_hand.two_stage.gain);
  ASSERT_EQ(u.gain.size(), 4U);
  for (int k = 0; k < 4; ++k)
    EXPECT_EQ(u.gain[static_cast<std::size_t>(k)], by_hand.two_stage.gain->gain(k / 2, k % 2));
  EXPECT_EQ(u.samples, run.du.rows());
  EXPECT_TRUE(std::isnan(u.crossfit_avg));  // closed loop: no cross-validation
  ASSERT_EQ(u.lengths.size(), 2U);
  EXPECT_EQ(u.lengths[1].met, u.accuracy.met);
}

TEST(ClosedLoopUnit, APrefixIsIdentifiedFromItsOwnRowsAlone) {
  // GIVEN a closed-loop experiment, and the same one with every row after the half changed
  const mc::Config config = pi_dither();
  const auto prepared = mc::prepare(config, 1);
  const auto plant = sim::make_plant("woodberry2x2");
  const mc::SeedController controller =
      mc::seed_controller(*prepared, 3, prepared->truth.gain.gain);
  ASSERT_TRUE(controller.controller) << controller.refused;
  const host::ClosedLoopRun run = mc::closed_loop_experiment(
      *prepared, {0, 3, 0}, *plant, *controller.controller, prepared->truth);
  const Eigen::Index half = run.experiment.U.rows() / 2;
  host::Experiment later_changed = run.experiment;
  Eigen::MatrixXd R = run.R;
  later_changed.U.bottomRows(later_changed.U.rows() - half) *= -3.0;
  later_changed.Y.bottomRows(later_changed.Y.rows() - half).array() += 0.7;
  R.bottomRows(R.rows() - half) *= 5.0;

  // WHEN the first half is identified in both
  const mc::GridEvaluation a = mc::evaluate_length_grid(*prepared, prepared->truth, run.experiment,
                                                        {50, 100}, mc::GridStart::cold, run.R);
  const mc::GridEvaluation b = mc::evaluate_length_grid(*prepared, prepared->truth, later_changed,
                                                        {50, 100}, mc::GridStart::cold, R);

  // THEN the half's estimate is the same: stage 1 and stage 2 saw only its rows
  ASSERT_EQ(a.results.size(), 1U);
  ASSERT_TRUE(a.results[0] && b.results[0]);
  ASSERT_TRUE(a.results[0]->gain && b.results[0]->gain);
  EXPECT_EQ(a.results[0]->gain->gain, b.results[0]->gain->gain);
  // … and it is stage 1's û of the half, not the half of the whole run's û.
  const host::Stage1Fit whole = host::project_on_reference(run.experiment.U, run.R);
  const host::Stage1Fit own =
      host::project_on_reference(run.experiment.U.topRows(half), run.R.topRows(half));
  EXPECT_GT((whole.u_hat.topRows(half) - own.u_hat).norm(), 1e-6 * own.u_hat.norm());
}

namespace {

mc::Config dmc_setpoint(double controller_perturb) {
  mc::Config c;
  c.plant = "alatiqi4x4";
  c.designs = {"prbsUnc"};
  c.seeds = 3;
  c.noise_variance = 5e-4;
  c.closed_loop.controller = kDmc;
  c.closed_loop.model_perturb_percent = controller_perturb;
  mc::normalise(c);
  return c;
}

// The controller's first move from rest when CV 1's setpoint steps by 0.1.
std::vector<double> first_move(const mc::SeedController& made) {
  EXPECT_TRUE(made.controller) << made.refused;
  if (!made.controller) return {};
  excite::sim::control::Controller& controller = *made.controller;
  const std::vector<double> y(4, 0.0), offsets(4, 0.0);
  const std::vector<double> sp{0.1, 0.0, 0.0, 0.0};
  std::vector<double> u(4, 0.0);
  controller.reset();
  (void)controller.step(y, sp, offsets, u);
  return u;
}

}  // namespace

TEST(ClosedLoopUnit, TheDmcsModelIsPerturbedPerSeedAndReproducibly) {
  const auto nominal = mc::prepare(dmc_setpoint(0.0), 1);
  const auto perturbed = mc::prepare(dmc_setpoint(10.0), 1);
  ASSERT_TRUE(perturbed->controller_model);
  EXPECT_FALSE(nominal->controller_model);
  const Eigen::MatrixXd& g0 = nominal->truth.gain.gain;
  const std::vector<double> own = first_move(mc::seed_controller(*nominal, 1, g0));
  EXPECT_EQ(own, first_move(mc::seed_controller(*nominal, 2, g0)));  // no perturbation
  const std::vector<double> one = first_move(mc::seed_controller(*perturbed, 1, g0));
  const std::vector<double> two = first_move(mc::seed_controller(*perturbed, 2, g0));
  EXPECT_NE(one, own);
  EXPECT_NE(one, two);
  EXPECT_EQ(one, first_move(mc::seed_controller(*perturbed, 1, g0)));  // the same draw again
}

TEST(ClosedLoopUnit, APiControllersModelIsNotPerturbed) {
  try {
    (void)mc::prepare(pi_dither(10.0), 1);
    FAIL() << "a PI controller's model was perturbed";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("--controller-perturb = 10 with "), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("expected 0 for a PI controller"), std::string::npos)
        << e.what();
  }
}

TEST(ClosedLoopUnit, ASeedWhoseModelTheDmcRefusesIsNotRunAndCountedApart) {
  // GIVEN the first seed whose ±60 % controller model of alatiqi4x4 has a principal minor of
  // the other sign than the plant's (found here, not assumed), and one whose model is fine
  const sim::TransferMatrix nominal = sim::library_plant("alatiqi4x4");
  std::uint64_t refused = 0, fine = 0;
  for (std::uint64_t s = 1; s <= 200 && (refused == 0 || fine == 0); ++s) {
    const sim::TransferMatrix model =
        sim::perturbed_plant(nominal, 60.0, mc::controller_model_seed(s));
    const bool ic = sim::control::check_integral_controllability(model.static_gain(),
                                                                 nominal.static_gain(), "m")
                        .ok();
    if (!ic && refused == 0) refused = s;
    if (ic && fine == 0) fine = s;
  }
  ASSERT_NE(refused, 0U) << "no seed of 200 draws a model that is not integrally controllable";
  ASSERT_NE(fine, 0U);
  mc::Config c = prbs_unc("alatiqi4x4", kDmc, refused, 60.0);
  c.perturb_percent = 1.0;  // the true plant perturbed too: its G(0) is kept as a run's is
  const auto prepared = mc::prepare(c, 1);

  // WHEN its unit is run
  const mc::UnitResult u = mc::run_unit(*prepared, {0, refused, 0});

  // THEN it says why it was not run, meets nothing, and reads back as such
  EXPECT_NE(u.not_run.find("integrally controllable"), std::string::npos) << u.not_run;
  EXPECT_EQ(u.samples, prepared->designs[0].table.rows());
  ASSERT_EQ(u.lengths.size(), 2U);
  EXPECT_FALSE(u.lengths[0].met || u.lengths[1].met || u.accuracy.met);
  const std::filesystem::path file = std::filesystem::path(testing::TempDir()) / "not-run.json";
  { std::ofstream(file) << mc::unit_json(u).dump(1); }
  EXPECT_EQ(mc::read_unit(file).not_run, u.not_run);
  EXPECT_EQ(u.true_gain.size(), 16U);
  EXPECT_NO_THROW(mc::check_unit(mc::read_unit(file), c, {0, refused, 0}, 4, 4, file));

  // … and the summary counts it apart: its shares and T90 are over the seeds run.
  mc::UnitResult ran = u;
  ran.not_run.clear();
  ran.seed = fine;
  ran.accuracy.met = true;
  ran.lengths[1].met = true;
  c.seeds = 2;
  c.first_seed = std::min(refused, fine);
  const nlohmann::json summary = mc::summary_json(c, {u, ran});
  const nlohmann::json& d = summary["designs"][0];
  EXPECT_EQ(d["seeds"], 1);
  EXPECT_EQ(d["criterion"]["of"], 1);
  EXPECT_EQ(d["not_run"]["seeds"], 1);
  EXPECT_EQ(
      d["not_run"]["first"].get<std::string>().rfind("seed " + std::to_string(refused) + ": ", 0),
      0U);
  EXPECT_NE(mc::summary_text(summary).find("prbsUnc: 1 seeds not run, not in its shares or T90"),
            std::string::npos)
      << mc::summary_text(summary);
}

TEST(ClosedLoopUnit, OptionsAreCheckedByName) {
  const auto refused = [](mc::Config c, const std::string& expected) {
    try {
      mc::normalise(c);
      ADD_FAILURE() << "accepted; expected " << expected;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  mc::Config c;
  c.plant = "alatiqi4x4";
  c.seeds = 1;
  c.closed_loop.controller = kDmc;
  mc::Config all = c;
  mc::normalise(all);  // every plain preset, none directional
  EXPECT_FALSE(all.designs.empty());
  for (const std::string& d : all.designs)
    EXPECT_FALSE(host::find_preset(d).uses_directions()) << d;
  mc::Config directional = c;
  directional.designs = {"prbsSimDir"};
  refused(directional, "--designs = prbsSimDir, expected a plain preset");
  mc::Config excitation = c;
  excitation.closed_loop.excitation = "both";
  refused(excitation, "--excitation = both, expected setpoint or mv");
  mc::Config method = c;
  method.closed_loop.method = "projection";
  refused(method, "--method = projection, expected two-stage or direct");
  mc::Config disturbance = c;
  disturbance.closed_loop.disturbance_std = 0.1;
  refused(disturbance, "--disturbance-tau-min = 0.000000, expected a time constant > 0");
  mc::Config model = c;
  model.closed_loop.model_perturb_percent = 100.0;
  refused(model, "--controller-perturb = 100, expected a number of percent, 0 <= X < 100");
  mc::Config directions = c;
  directions.closed_loop.directions = "input";
  refused(directions, "--directions = input, expected none or output");
  directions.closed_loop.directions = "output";
  directions.closed_loop.excitation = "mv";
  refused(directions, "--directions = output with --excitation = mv, expected setpoint excitation");
  mc::Config phase = c;
  phase.closed_loop.prbs_phase = 3;
  phase.closed_loop.excitation = "mv";
  refused(phase, "--prbs-phase = 3 with --excitation mv, expected 0");
  phase.closed_loop.excitation = "setpoint";
  phase.closed_loop.prbs_phase = mc::kMaxPrbsPhase + 1;
  refused(phase, "--prbs-phase = 1000001, expected 0 to 1000000");
}

// --prbs-phase K: every seed's r is the same, so a run measures one realisation of it; K
// starts the PRBS K switching intervals in, the same r rows K·hold on (a whole period at the
// loop's pace).
TEST(ClosedLoopUnit, APrbsPhaseStartsTheDesignsRLater) {
  mc::Config config = prbs_unc("alatiqi4x4", kDmc, 1);
  const auto first = mc::prepare(config, 1);
  config.closed_loop.prbs_phase = 7;
  const auto later = mc::prepare(config, 1);
  const Eigen::MatrixXd& r0 = first->designs[0].table;
  const Eigen::MatrixXd& r7 = later->designs[0].table;
  const Eigen::Index hold = first->designs[0].plan->recipe.sources[0].prbs.hold_samples;
  ASSERT_EQ(r0.rows(), r7.rows());
  ASSERT_EQ(r0.rows() % hold, 0);
  const Eigen::Index rows = r0.rows(), shift = 7 * hold;
  EXPECT_EQ(Eigen::MatrixXd(r7.topRows(rows - shift)),
            Eigen::MatrixXd(r0.bottomRows(rows - shift)));
  EXPECT_EQ(Eigen::MatrixXd(r7.bottomRows(shift)), Eigen::MatrixXd(r0.topRows(shift)));
}

// --directions output: the same preset's signals, put along the prior's output directions W
// (G(0) = W Σ Vᵀ): Wᵀ r is, source by source, the plain design's CV signal rescaled.
TEST(ClosedLoopUnit, OutputDirectionsPutEachPlainSignalAlongOneOfThePriorsOutputDirections) {
  mc::Config plain_config = prbs_unc("alatiqi4x4", kDmc, 1);
  mc::Config along_config = plain_config;
  along_config.closed_loop.directions = "output";
  const auto plain = mc::prepare(plain_config, 1);
  const auto along = mc::prepare(along_config, 1);
  const Eigen::MatrixXd& r_plain = plain->designs[0].table;
  const Eigen::MatrixXd& r_along = along->designs[0].table;
  ASSERT_EQ(r_plain.rows(), r_along.rows());
  const Eigen::MatrixXd& W = plain->truth.gain.output_directions;  // the case study's prior
  const Eigen::MatrixXd turned = r_along * W;                      // row k: (Wᵀ r(k))ᵀ
  for (Eigen::Index i = 0; i < r_plain.cols(); ++i) {
    // The same signal up to one factor: |cos| of the angle between the columns is 1.
    const double cosine = std::abs(turned.col(i).dot(r_plain.col(i))) /
                          (turned.col(i).norm() * r_plain.col(i).norm());
    EXPECT_NEAR(cosine, 1.0, 1e-12) << "direction " << i;
  }
  // And not the plain design: its CV signals are not along W.
  const Eigen::MatrixXd plain_turned = r_plain * W;
  EXPECT_LT(std::abs(plain_turned.col(0).dot(r_plain.col(0))) /
                (plain_turned.col(0).norm() * r_plain.col(0).norm()),
            0.99);
}

TEST(ClosedLoopUnit, RunJsonKeepsTheClosedLoopAndAnOlderFolderReadsAsOpenLoop) {
  mc::Config c = pi_dither(12.5);  // not prepared: run.json keeps what it is given
  c.closed_loop.disturbance_std = 0.3;
  c.closed_loop.disturbance_tau_min = 20.0;
  c.closed_loop.method = "direct";
  const std::filesystem::path dir = std::filesystem::path(testing::TempDir()) / "cl-run-json";
  std::filesystem::create_directories(dir);
  nlohmann::json j = mc::config_json(c);
  { std::ofstream(dir / "run.json") << j.dump(2); }
  const mc::Config back = mc::read_config(dir / "run.json");
  EXPECT_EQ(back.closed_loop.controller, kPi);
  EXPECT_EQ(back.closed_loop.excitation, "mv");
  EXPECT_EQ(back.closed_loop.method, "direct");
  EXPECT_EQ(back.closed_loop.model_perturb_percent, 12.5);
  EXPECT_EQ(back.closed_loop.disturbance_std, 0.3);
  EXPECT_EQ(back.closed_loop.disturbance_tau_min, 20.0);
  EXPECT_EQ(back.closed_loop.limit_fraction, c.closed_loop.limit_fraction);
  EXPECT_EQ(back.designs, c.designs);

  mc::Config along = prbs_unc("alatiqi4x4", kDmc, 1);
  along.closed_loop.directions = "output";
  nlohmann::json k = mc::config_json(along);
  { std::ofstream(dir / "run.json") << k.dump(2); }
  EXPECT_EQ(mc::read_config(dir / "run.json").closed_loop.directions, "output");
  k["closed_loop"].erase("directions");  // a folder of a run before --directions
  { std::ofstream(dir / "run.json") << k.dump(2); }
  EXPECT_EQ(mc::read_config(dir / "run.json").closed_loop.directions, "none");
  EXPECT_EQ(mc::read_config(dir / "run.json").closed_loop.switching, "loop");
  k["closed_loop"].erase("switching");  // a folder of a run before --switching: plant's pace
  { std::ofstream(dir / "run.json") << k.dump(2); }
  EXPECT_EQ(mc::read_config(dir / "run.json").closed_loop.switching, "plant");
  EXPECT_EQ(mc::read_config(dir / "run.json").closed_loop.prbs_phase, 0U);
  k["closed_loop"]["prbs_phase"] = 4;
  { std::ofstream(dir / "run.json") << k.dump(2); }
  EXPECT_EQ(mc::read_config(dir / "run.json").closed_loop.prbs_phase, 4U);
  k["closed_loop"].erase("prbs_phase");  // a folder of a run before --prbs-phase: phase 0
  { std::ofstream(dir / "run.json") << k.dump(2); }
  EXPECT_EQ(mc::read_config(dir / "run.json").closed_loop.prbs_phase, 0U);
  k["closed_loop"]["prbs_phase"] = -1;
  { std::ofstream(dir / "run.json") << k.dump(2); }
  EXPECT_THROW((void)mc::read_config(dir / "run.json"), std::runtime_error);  // refused by name
  k["closed_loop"]["prbs_phase"] = 0;
  k["closed_loop"]["switching"] = "loop; rm -rf /";  // would reach the Slurm command line
  { std::ofstream(dir / "run.json") << k.dump(2); }
  EXPECT_THROW((void)mc::read_config(dir / "run.json"), std::runtime_error);  // refused by name

  j.erase("closed_loop");  // a folder of a run before issue 41 §4
  { std::ofstream(dir / "run.json") << j.dump(2); }
  EXPECT_FALSE(mc::read_config(dir / "run.json").closed_loop.on());
}

TEST(ClosedLoopUnit, TheMeasuredCvsAreCountedAgainstTheControllersCvTestLimits) {
  // GIVEN a DMC on woodberry2x2 with CV test limits ±0.2, and r at all of them (fraction 1:
  // the CVs overshoot their setpoints, so some rows are outside)
  sim::control::ControllerFile file;
  file.kind = sim::control::ControllerKind::dmc;
  file.model.plant = "woodberry2x2";
  file.model.delay_samples = 1;
  file.dmc.prediction_horizon = 60;
  file.dmc.control_horizon = 3;
  file.dmc.mv.assign(2, sim::control::MvSettings{});
  file.dmc.cv.assign(2, sim::control::CvSettings{});
  for (sim::control::CvSettings& cv : file.dmc.cv) {
    cv.limit_low = -0.2;
    cv.limit_high = 0.2;
  }
  file.mv_given = file.cv_given = true;
  const std::filesystem::path path = std::filesystem::path(testing::TempDir()) / "wb.dmc.toml";
  { std::ofstream(path) << sim::control::controller_file_toml(file); }
  mc::Config c = prbs_unc("woodberry2x2", path.string(), 2);
  c.length_step_percent = 0;
  c.closed_loop.limit_fraction = 1.0;
  const auto prepared = mc::prepare(c, 1);

  // WHEN the unit runs, and its run is made again to count by hand
  const mc::UnitResult u = mc::run_unit(*prepared, {0, 2, 0});
  const auto plant = sim::make_plant("woodberry2x2");
  const mc::SeedController controller =
      mc::seed_controller(*prepared, 2, prepared->truth.gain.gain);
  ASSERT_TRUE(controller.controller);
  const Eigen::MatrixXd Y = mc::closed_loop_experiment(*prepared, {0, 2, 0}, *plant,
                                                       *controller.controller, prepared->truth)
                                .experiment.Y;
  const Eigen::ArrayXXd share = Y.array().abs() / 0.2;
  long long outside = 0;
  for (Eigen::Index k = 0; k < Y.rows(); ++k) outside += share.row(k).maxCoeff() > 1.0 ? 1 : 0;

  // THEN the unit's figures are the hand count's, and they are a violation
  EXPECT_DOUBLE_EQ(u.cv_peak_ratio, share.maxCoeff());
  EXPECT_EQ(u.cv_violation_rows, outside);
  EXPECT_GT(u.cv_violation_rows, 0);
  const std::filesystem::path unit_file = std::filesystem::path(testing::TempDir()) / "cv.json";
  { std::ofstream(unit_file) << mc::unit_json(u).dump(1); }
  const mc::UnitResult back = mc::read_unit(unit_file);
  EXPECT_EQ(back.cv_violation_rows, u.cv_violation_rows);
  EXPECT_EQ(back.cv_peak_ratio, u.cv_peak_ratio);
}
