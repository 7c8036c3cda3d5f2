// SPDX-License-Identifier: MIT
#include "host/design/closed_loop_design.hpp"

#include <Eigen/QR>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "firmware/signal/recipe.hpp"
#include "host/design/prbs_shift.hpp"
#include "host/design/table.hpp"

namespace excite::host {
namespace {

// v as printf's %g (six significant digits).
std::string g_text(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// Starts every PRBS source of d `bits` of its bits further into its m-sequence (modulo its
// period) and makes the table again: another realisation of the same signal, its spectrum and
// amplitude unchanged. Throws std::invalid_argument when d has no PRBS source to move.
void start_prbs_later(Design& d, std::uint32_t bits, const PresetInfo& preset) {
  signal::Recipe& r = d.plan->recipe;
  int moved = 0;
  for (std::uint32_t i = 0; i < r.source_count; ++i) {
    if (r.sources[i].kind != signal::SourceKind::prbs) continue;
    advance_prbs(r.sources[i].prbs, bits);
    ++moved;
  }
  if (moved == 0) {
    throw std::invalid_argument("PRBS phase = " + std::to_string(bits) + " with preset " +
                                std::string(preset.acronym) +
                                ", expected 0 (it has no PRBS to start later)");
  }
  d.table = make_table(r);
  d.notes.push_back("the PRBS started " + std::to_string(bits) +
                    " switching intervals into its sequence");
}

void mark(Design& d, plan::Excitation e, const std::string& what) {
  d.plan->meta.excitation = e;
  std::string provenance = std::string(plan::text_of(d.plan->meta.provenance)) + " " + what;
  if (provenance.size() >= plan::kProvenanceCapacity)
    provenance.resize(plan::kProvenanceCapacity - 1);
  plan::set_text(d.plan->meta.provenance, provenance);
}

// The preset's setpoint mix turned into the prior's output directions: r = c·W s (W of
// G(0) = W Σ Vᵀ, p × p), c the largest scale that keeps every CV within its amplitude.
void rotate_into_output_directions(Design& d, const Eigen::MatrixXd& gain,
                                   const Eigen::VectorXd& amplitude, const PresetInfo& preset) {
  const Eigen::Index p = amplitude.size();
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(gain, Eigen::ComputeFullU);
  const Eigen::MatrixXd& W = svd.matrixU();  // p × p, output directions
  // r = c·W s: the preset's mix (channels × sources, each channel a_c · s_c) rotated.
  signal::Recipe& r = d.plan->recipe;
  Eigen::MatrixXd mix(p, r.source_count);
  for (Eigen::Index c = 0; c < p; ++c) {
    for (Eigen::Index i = 0; i < mix.cols(); ++i) {
      mix(c, i) = r.mix[static_cast<std::size_t>(c)][static_cast<std::size_t>(i)] / amplitude(c);
    }
  }
  const Eigen::MatrixXd rotated = W * mix;
  for (Eigen::Index c = 0; c < p; ++c) {
    for (Eigen::Index i = 0; i < mix.cols(); ++i) {
      r.mix[static_cast<std::size_t>(c)][static_cast<std::size_t>(i)] = rotated(c, i);
    }
  }
  const Table turned = make_table(d.plan->recipe);
  double scale = 1e300;
  for (Eigen::Index c = 0; c < p; ++c) {
    const double peak = turned.col(c).cwiseAbs().maxCoeff();
    if (peak > 0.0) scale = std::min(scale, amplitude(c) / peak);
  }
  for (Eigen::Index c = 0; c < p; ++c) {
    for (Eigen::Index i = 0; i < mix.cols(); ++i) {
      r.mix[static_cast<std::size_t>(c)][static_cast<std::size_t>(i)] *= scale;
    }
  }
  d.table = make_table(d.plan->recipe);
  d.notes.push_back(
      "setpoint directions: r(k) = c * W * s(k), W the prior's output "
      "directions (G(0) = W Sigma V'), c = " +
      g_text(scale) + " keeps every CV within its amplitude");
  plan::set_text(d.plan->meta.design_name,
                 std::string(preset.acronym).substr(0, plan::kNameCapacity - 5) + "OutDir");
}

// The MV moves r asks for in steady state, u(k) = G(0)⁺ r(k) (G(0) = prior.gain, CVs × MVs),
// kept within mv_fraction of each MV's room by scaling r down (never up: the CV limits size it
// first). Without MV limits: nothing.
void fit_into_mv_room(Design& d, const Eigen::MatrixXd& gain, const SetpointDesignRequest& req) {
  const Eigen::Index n = req.mv_low.size();
  if (n == 0 && req.mv_high.size() == 0) return;
  if (req.mv_high.size() != n || gain.cols() != n || gain.rows() != d.table.cols()) {
    throw std::invalid_argument(
        "MV limits = " + std::to_string(n) + " low, " + std::to_string(req.mv_high.size()) +
        " high, expected one pair per MV of a prior G(0) with one row per CV (" +
        std::to_string(gain.rows()) + " x " + std::to_string(gain.cols()) + ")");
  }
  if (!(req.mv_fraction > 0.0 && req.mv_fraction <= 1.0)) {
    throw std::invalid_argument("MV room fraction = " + g_text(req.mv_fraction) +
                                ", expected 0 < f <= 1");
  }
  const Eigen::MatrixXd moves =
      d.table *
      gain.completeOrthogonalDecomposition().pseudoInverse().transpose();  // samples × MVs
  double scale = 1.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double lo = req.mv_low(i), hi = req.mv_high(i);
    if (!(lo < 0.0 && hi > 0.0)) {
      throw std::invalid_argument("MV " + std::to_string(i + 1) + " limits = " + g_text(lo) + ":" +
                                  g_text(hi) + ", expected low < 0 < high");
    }
    const double room = req.mv_fraction * std::min(-lo, hi);  // infinite: no limit
    const double peak = moves.col(i).cwiseAbs().maxCoeff();
    if (peak > 0.0 && std::isfinite(room)) scale = std::min(scale, room / peak);
  }
  if (scale < 1.0) {
    signal::Recipe& r = d.plan->recipe;
    for (std::size_t c = 0; c < static_cast<std::size_t>(d.table.cols()); ++c) {
      for (std::size_t i = 0; i < r.source_count; ++i) r.mix[c][i] *= scale;
    }
    d.table = make_table(r);
  }
  d.notes.push_back("MV room: r scaled by " + g_text(scale) +
                    " so the steady-state moves inv(G(0)) r stay within " +
                    g_text(req.mv_fraction) + " x each MV's limits");
}

}  // namespace

Design design_setpoint_excitation(const PriorKnowledge& prior, const PresetInfo& preset,
                                  const SetpointDesignRequest& req, std::uint64_t created_unix_s) {
  if (preset.uses_directions()) {
    throw std::invalid_argument("preset = " + std::string(preset.acronym) +
                                ", expected a plain preset for setpoint excitation (its "
                                "directions are the output directions: --directions output)");
  }
  const auto p = static_cast<Eigen::Index>(req.cv_names.size());
  if (p < 1 || p > static_cast<Eigen::Index>(signal::kMaxChannels)) {
    throw std::invalid_argument("CVs = " + std::to_string(p) + ", expected 1 to " +
                                std::to_string(signal::kMaxChannels));
  }
  if (req.cv_low.size() != p || req.cv_high.size() != p) {
    throw std::invalid_argument("CV test limits = " + std::to_string(req.cv_low.size()) +
                                ", expected one pair per CV (" + std::to_string(p) + ")");
  }
  if (!(req.fraction > 0.0 && req.fraction <= 1.0)) {
    throw std::invalid_argument("limit fraction = " + g_text(req.fraction) +
                                ", expected 0 < f <= 1");
  }
  PriorKnowledge cvs = prior;  // the time scales and T of the plant; the CVs as channels
  cvs.inputs.clear();
  cvs.gain.resize(0, 0);
  cvs.sizing = Sizing::input_amplitude;
  Eigen::VectorXd amplitude(p);
  for (Eigen::Index c = 0; c < p; ++c) {
    const double lo = req.cv_low(c), hi = req.cv_high(c);
    const std::string& name = req.cv_names[static_cast<std::size_t>(c)];
    if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo < 0.0 && hi > 0.0)) {
      throw std::invalid_argument("--limit " + name + " = " + g_text(lo) + ":" + g_text(hi) +
                                  ", expected finite test limits with low < 0 < high for "
                                  "setpoint excitation");
    }
    amplitude(c) = req.fraction * std::min(-lo, hi);
    cvs.inputs.push_back({name, amplitude(c), lo, hi});
  }
  Design d = design_preset(cvs, preset, created_unix_s);
  if (req.prbs_phase > 0) start_prbs_later(d, req.prbs_phase, preset);
  if (req.along_output_directions) {
    if (prior.gain.rows() != p) {
      throw std::invalid_argument("prior gain rows = " + std::to_string(prior.gain.rows()) +
                                  ", expected " + std::to_string(p) +
                                  " (one per CV) for output directions");
    }
    rotate_into_output_directions(d, prior.gain, amplitude, preset);
  }
  d.notes.push_back(
      "setpoint excitation: r in CV units, amplitude per CV = " + g_text(req.fraction) +
      " x its test limit; under integral action u ~ inv(G(0)) r");
  fit_into_mv_room(d, prior.gain, req);
  mark(d, plan::Excitation::setpoint, "closed-loop setpoint");
  return d;
}

Design design_mv_dither(const PriorKnowledge& prior, const PresetInfo& preset,
                        std::uint64_t created_unix_s) {
  Design d = design_preset(prior, preset, created_unix_s);
  d.notes.push_back("MV dither: the table is added to the controller's MV output");
  mark(d, plan::Excitation::mv, "closed-loop mv dither");
  return d;
}

}  // namespace excite::host
