// SPDX-License-Identifier: MIT
#include "host/identify/identification_text.hpp"

#include <cmath>

#include "host/output/text_table.hpp"

namespace excite::host {
namespace {

std::string with_unit(const std::string& name, const std::string& unit) {
  return unit.empty() || unit == "-" ? name : name + " [" + unit + "]";
}

// σ_i ± SE, the direction angles' uncertainty and the principal minors at risk.
void print_uncertainty(std::ostream& out, const GainUncertainty& u) {
  TextTable t({"direction", "sigma", "+-", "v angle +- [deg]", "w angle +- [deg]"});
  for (Eigen::Index i = 0; i < u.singular_values.size(); ++i) {
    t.add_row({std::to_string(i + 1), num(u.singular_values(i), 5), num(u.singular_value_se(i), 3),
               num(u.input_angle_se_deg(i), 3), num(u.output_angle_se_deg(i), 3)});
  }
  t.print(out);
  if (u.principal_minors.empty()) return;
  out << "principal minors: " << u.principal_minors.size() << ", " << u.sign_uncertain_minors
      << " whose sign a gain error within its 95 % interval can flip";
  const PrincipalMinor& det = u.principal_minors.back();
  out << "; det G(0) = " << num(det.value, 4) << " +- " << num(det.std_error, 3)
      << (det.sign_uncertain ? " (sign undetermined: integral controllability at risk)" : "")
      << '\n';
  for (const PrincipalMinor& pm : u.principal_minors) {
    if (!pm.sign_uncertain || &pm == &det) continue;
    out << "  minor of rows/columns";
    for (const int k : pm.rows) out << ' ' << k + 1;
    out << " = " << num(pm.value, 4) << " +- " << num(pm.std_error, 3) << '\n';
  }
}

// A line per gain of row o whose reported 95 % interval is wider than K ± 1.96·SE, and why.
void print_projected_gains(std::ostream& out, const IdentifiedModel& m, int o,
                           const runlog::RunLog& log) {
  for (int i = 0; i < m.inputs; ++i) {
    const ElementEstimate& e = m.element(o, i);
    if (!e.projected_gain) continue;
    const GainBounds reported = gain_interval_95(e);
    const double half = 1.96 * e.std_error.gain;  // a projection the SE's widening overtook
    if (std::isfinite(half) && reported.upper - reported.lower <= 2.02 * half) continue;
    out << "  " << log.input_names[static_cast<std::size_t>(i)] << ": K's 95 % interval "
        << num(reported.lower, 4) << " to " << num(reported.upper, 4);
    if (std::isfinite(half)) {
      out << " (K +- 1.96 SE: " << num(e.value.gain - half, 4) << " to "
          << num(e.value.gain + half, 4) << ")";
    } else {
      out << " (K has no standard error)";
    }
    out << ": " << e.projected_gain->why << '\n';
  }
}

}  // namespace

std::string element_name(const runlog::RunLog& log, int o, int i) {
  return log.output_names[static_cast<std::size_t>(o)] + "<-" +
         log.input_names[static_cast<std::size_t>(i)];
}

void print_identification(std::ostream& out, const IdentificationResult& r,
                          const runlog::RunLog& log) {
  const IdentifiedModel& m = r.model;
  for (int o = 0; o < m.outputs; ++o) {
    const auto oi = static_cast<std::size_t>(o);
    out << "output " << with_unit(log.output_names[oi], log.output_units[oi])
        << ": fit = " << num(r.fits[oi].fit_percent) << " %\n";
    const ResidualTests& tests = r.fits[oi].residual_tests;
    if (tests.lags > 0) {
      out << "  residual " << (tests.white() ? "white" : "NOT white")
          << " (Q = " << num(tests.whiteness, 3) << ", 99 % limit " << num(tests.whiteness_limit, 3)
          << ", " << tests.lags << " lags)\n";
    }
    if (!r.fits[oi].inputs_together.empty()) {
      out << "  inputs together: " << r.fits[oi].inputs_together << '\n';
    }
    // A column per parameter that some element of the row has (its structure's), "-" where
    // an element's structure has no such parameter.
    std::vector<int> shown;
    for (int k = 0; k < kParameters; ++k) {
      bool used = false;
      for (int i = 0; i < m.inputs; ++i) {
        const ElementEstimate& e = m.element(o, i);
        used |= e.estimated() && is_free(e.value.structure, k);
      }
      if (used || k <= kTp2) shown.push_back(k);
    }
    std::vector<std::string> header{"input", "grade", "structure"};
    for (const int k : shown) {
      const auto p = static_cast<Parameter>(k);
      header.push_back(std::string(parameter_name(p)) +
                       (k == kGain || k == kDamping ? "" : " [min]"));
      header.push_back("+-");
    }
    header.push_back("status");
    TextTable t(header);
    for (int i = 0; i < m.inputs; ++i) {
      const ElementEstimate& e = m.element(o, i);
      std::string status = to_string(e.status);
      if (!e.reason.empty()) status += ": " + e.reason;
      for (const std::string& b : e.on_bound()) status += "; " + b;
      const auto ii = static_cast<std::size_t>(i);
      std::vector<std::string> row{with_unit(log.input_names[ii], log.input_units[ii]),
                                   to_string(e.grade),
                                   e.estimated() ? to_string(e.value.structure) : "-"};
      for (const int k : shown) {
        const bool has = !e.estimated() || is_free(e.value.structure, k);
        row.push_back(has ? num(e.value[k]) : "-");
        row.push_back(has ? num(e.std_error[k]) : "-");
      }
      row.push_back(status);
      t.add_row(row);
    }
    t.print(out);
    for (int i = 0; i < m.inputs; ++i) {  // what kept each element from grade A
      const ElementEstimate& e = m.element(o, i);
      if (e.grade_reason.empty()) continue;
      out << "  " << log.input_names[static_cast<std::size_t>(i)] << ": " << to_string(e.grade)
          << ", " << e.grade_reason << '\n';
    }
    print_projected_gains(out, m, o, log);
    out << '\n';
  }
  if (r.gain) {
    out << "identified G(0): singular values";
    for (Eigen::Index i = 0; i < r.gain->singular_values.size(); ++i) {
      out << ' ' << num(r.gain->singular_values(i), 5);
    }
    out << ", condition number " << num(r.gain->condition_number, 5) << '\n';
    if (const auto& u = r.gain_uncertainty) print_uncertainty(out, *u);
  } else {
    out << "identified G(0): " << r.gain_unavailable_reason << '\n';
  }
}

void print_noise_orders(std::ostream& out, const std::vector<ArNoiseModel>& noise,
                        const runlog::RunLog& log) {
  out << "noise model (by BIC: white, AR(n) or ARMA(1,1)):";
  for (std::size_t o = 0; o < noise.size(); ++o) {
    out << (o == 0 ? " " : ", ") << log.output_names.at(o) << ' ' << noise[o].name();
  }
  out << '\n';
}

void print_closed_loop(std::ostream& out, const ClosedLoopIdentification& id,
                       const runlog::RunLog& log, bool direct) {
  const IdentifiedModel& other = direct ? id.two_stage.model : id.direct.model;
  out << (direct ? "two-stage estimate (cross-check)"
                 : "direct fit on the applied u "
                   "(cross-check)")
      << ": G(0) =";
  for (int o = 0; o < other.outputs; ++o) {
    out << (o == 0 ? " [" : "; ");
    for (int i = 0; i < other.inputs; ++i) {
      const ElementEstimate& e = other.element(o, i);
      out << (i == 0 ? "" : " ") << (e.estimated() ? num(e.value.static_gain(), 4) : "-") << " +- "
          << (e.estimated() ? num(e.std_error.gain, 2) : "-");
    }
  }
  out << "]\n";
  if (id.feedback_bias.empty()) {
    out << "no feedback bias suspected: the two G(0) agree within 2 sigma in every "
           "element\n";
    return;
  }
  out << "feedback bias suspected in " << id.feedback_bias.size()
      << " element(s) (two-stage and direct G(0) differ by more than 2 sigma):\n";
  for (const GainDisagreement& d : id.feedback_bias) {
    out << "  " << element_name(log, d.output, d.input) << ": two-stage " << num(d.two_stage, 4)
        << ", direct " << num(d.direct, 4) << " (2 sigma = " << num(2.0 * d.sigma, 3) << ")\n";
  }
}

}  // namespace excite::host
