// SPDX-License-Identifier: MIT
#include "sim/control/dmc.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "base/config/document.hpp"
#include "base/config/error.hpp"

namespace excite::sim::control {
namespace {

[[noreturn]] void refuse(const std::string& field, double value, const std::string& expected) {
  throw config::Error(field, config::format_number(value), expected);
}

bool finite(std::span<const double> v) {
  return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}

void check_settings(const StepModel& model, const DmcSettings& s) {
  if (model.inputs < 1 || model.outputs < 1 || model.coefficients.empty()) {
    throw config::Error("model", "(empty)", "a step-response model");
  }
  if (s.prediction_horizon < 1 || s.prediction_horizon > 100000) {
    refuse("dmc.prediction_horizon", s.prediction_horizon, "an integer 1..100000 (samples)");
  }
  if (s.control_horizon < 1 || s.control_horizon > s.prediction_horizon) {
    refuse("dmc.control_horizon", s.control_horizon,
           "an integer 1..prediction_horizon (" + std::to_string(s.prediction_horizon) + ")");
  }
  if (!(std::isfinite(s.slack_weight) && s.slack_weight > 0.0)) {
    refuse("dmc.slack_weight", s.slack_weight, "a finite number > 0");
  }
  if (s.max_qp_iterations < 1) refuse("dmc.max_qp_iterations", s.max_qp_iterations, "at least 1");
  if (s.mv.size() != static_cast<std::size_t>(model.inputs)) {
    refuse("mv", static_cast<double>(s.mv.size()),
           std::to_string(model.inputs) + " MV entries (the model's inputs)");
  }
  if (s.cv.size() != static_cast<std::size_t>(model.outputs)) {
    refuse("cv", static_cast<double>(s.cv.size()),
           std::to_string(model.outputs) + " CV entries (the model's outputs)");
  }
  for (std::size_t j = 0; j < s.mv.size(); ++j) {
    const MvSettings& m = s.mv[j];
    const std::string at = "mv[" + std::to_string(j) + "].";
    if (std::isnan(m.min) || m.min == kUnlimited) refuse(at + "min", m.min, "a number below max");
    if (std::isnan(m.max) || m.max == -kUnlimited || !(m.min < m.max)) {
      refuse(at + "max", m.max, "a number above min (" + config::format_number(m.min) + ")");
    }
    if (!(m.max_move > 0.0)) refuse(at + "max_move", m.max_move, "a move > 0");
    if (!(std::isfinite(m.move_suppression) && m.move_suppression > 0.0)) {
      refuse(at + "move_suppression", m.move_suppression, "a finite number > 0");
    }
  }
  for (std::size_t c = 0; c < s.cv.size(); ++c) {
    const CvSettings& v = s.cv[c];
    const std::string at = "cv[" + std::to_string(c) + "].";
    if (!(std::isfinite(v.weight) && v.weight >= 0.0))
      refuse(at + "weight", v.weight, "a finite number >= 0");
    if (v.zone && !(std::isfinite(v.zone_low) && std::isfinite(v.zone_high) && v.zone_low <= 0.0 &&
                    0.0 <= v.zone_high && v.zone_low < v.zone_high)) {
      refuse(at + "zone", v.zone_low,
             "[low, high] about the setpoint with low <= 0 <= high, low < high");
    }
    if (std::isnan(v.limit_low) || v.limit_low == kUnlimited) {
      refuse(at + "limits", v.limit_low, "a lower limit below the upper");
    }
    if (std::isnan(v.limit_high) || !(v.limit_low < v.limit_high)) {
      refuse(at + "limits", v.limit_high, "an upper limit above the lower");
    }
  }
}

}  // namespace

DmcController::DmcController(StepModel model, DmcSettings settings)
    : model_(std::move(model)), settings_(std::move(settings)) {
  check_settings(model_, settings_);
  n_ = model_.inputs;
  p_ = model_.outputs;
  P_ = settings_.prediction_horizon;
  M_ = settings_.control_horizon;
  window_ = std::max(P_, model_.horizon());
  const Eigen::Index rows = static_cast<Eigen::Index>(P_) * p_;
  const Eigen::Index moves = static_cast<Eigen::Index>(M_) * n_;

  // The dynamic matrix: block (j, i) = S_{j−i} for the move i made at k+i, seen at k+j.
  Su_.setZero(rows, moves);
  for (int j = 1; j <= P_; ++j) {
    for (int i = 0; i < M_ && i < j; ++i) {
      Su_.block(static_cast<Eigen::Index>(j - 1) * p_, static_cast<Eigen::Index>(i) * n_, p_, n_) =
          model_.at(j - i);
    }
  }
  Eigen::VectorXd q(rows);
  for (int j = 0; j < P_; ++j) {
    for (int c = 0; c < p_; ++c) {
      const CvSettings& v = settings_.cv[static_cast<std::size_t>(c)];
      q(static_cast<Eigen::Index>(j) * p_ + c) = v.zone ? 0.0 : v.weight;
    }
  }
  Eigen::VectorXd r(moves);
  for (int i = 0; i < M_; ++i) {
    for (int m = 0; m < n_; ++m) {
      r(static_cast<Eigen::Index>(i) * n_ + m) =
          settings_.mv[static_cast<std::size_t>(m)].move_suppression;
    }
  }
  SuT_Q_ = Su_.transpose() * q.asDiagonal();
  Eigen::MatrixXd H_moves = SuT_Q_ * Su_;
  H_moves.diagonal() += r;
  K_ = H_moves.llt().solve(SuT_Q_).topRows(n_);

  // Slack variables for the CVs with a soft bound.
  slack_of_.assign(static_cast<std::size_t>(p_), -1);
  for (int c = 0; c < p_; ++c) {
    const CvSettings& v = settings_.cv[static_cast<std::size_t>(c)];
    if (v.zone || std::isfinite(v.limit_low) || std::isfinite(v.limit_high)) {
      slack_of_[static_cast<std::size_t>(c)] = soft_++;
    }
  }
  const Eigen::Index nv = moves + soft_;
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(nv, nv);
  H.topLeftCorner(moves, moves) = H_moves;
  H.bottomRightCorner(soft_, soft_).diagonal().setConstant(settings_.slack_weight);

  // Constraint rows: their normals are fixed, their right-hand sides set every step.
  std::vector<Eigen::VectorXd> normals;
  const auto add = [&](RowKind kind, int index, int step, Eigen::VectorXd a) {
    rows_.push_back({kind, index, step});
    normals.push_back(std::move(a));
  };
  for (int i = 0; i < M_; ++i) {
    for (int m = 0; m < n_; ++m) {
      const MvSettings& mv = settings_.mv[static_cast<std::size_t>(m)];
      const Eigen::Index col = static_cast<Eigen::Index>(i) * n_ + m;
      if (std::isfinite(mv.max_move)) {
        Eigen::VectorXd a = Eigen::VectorXd::Zero(nv);
        a(col) = 1.0;
        add(RowKind::move_up, m, i, a);
        add(RowKind::move_down, m, i, -a);
      }
      Eigen::VectorXd sum = Eigen::VectorXd::Zero(nv);  // u(k+i) − u(k−1) = Σ_{l≤i} Δu(k+l)
      for (int l = 0; l <= i; ++l) sum(static_cast<Eigen::Index>(l) * n_ + m) = 1.0;
      if (std::isfinite(mv.max)) add(RowKind::box_up, m, i, sum);
      if (std::isfinite(mv.min)) add(RowKind::box_down, m, i, -sum);
    }
  }
  for (int c = 0; c < p_; ++c) {
    const int s = slack_of_[static_cast<std::size_t>(c)];
    if (s < 0) continue;
    const CvSettings& v = settings_.cv[static_cast<std::size_t>(c)];
    const bool upper = v.zone || std::isfinite(v.limit_high);
    const bool lower = v.zone || std::isfinite(v.limit_low);
    for (int j = 1; j <= P_; ++j) {
      const Eigen::Index row = static_cast<Eigen::Index>(j - 1) * p_ + c;
      // A prediction the moves cannot reach (within a dead time) gets no row: its slack
      // would otherwise be forced up by what no move can change.
      if (Su_.row(row).cwiseAbs().maxCoeff() == 0.0) continue;
      Eigen::VectorXd a = Eigen::VectorXd::Zero(nv);
      a.head(moves) = Su_.row(row).transpose();
      a(moves + s) = -1.0;
      if (upper) add(RowKind::cv_up, c, j, a);
      if (lower) {
        a.head(moves) = -Su_.row(row).transpose();
        add(RowKind::cv_down, c, j, a);
      }
    }
    Eigen::VectorXd a = Eigen::VectorXd::Zero(nv);
    a(moves + s) = -1.0;
    add(RowKind::slack, c, 0, a);
  }
  Eigen::MatrixXd A(static_cast<Eigen::Index>(normals.size()), nv);
  for (std::size_t i = 0; i < normals.size(); ++i)
    A.row(static_cast<Eigen::Index>(i)) = normals[i].transpose();
  qp_.emplace(H, A, settings_.max_qp_iterations);

  prediction_.setZero(static_cast<Eigen::Index>(window_ + 1) * p_);
  u_prev_.setZero(n_);
  offset_prev_.setZero(n_);
  status_.assign(static_cast<std::size_t>(n_), MvStatus::ok);
  f_.setZero(rows);
  e_.setZero(rows);
  g_.setZero(nv);
  b_.setZero(static_cast<Eigen::Index>(rows_.size()));
  x_.setZero(nv);
  applied_move_.setZero(n_);
  cur_.setZero(n_);
}

void DmcController::reset() noexcept {
  prediction_.setZero();
  u_prev_.setZero();
  offset_prev_.setZero();
  std::fill(status_.begin(), status_.end(), MvStatus::ok);
  qp_->forget();
}

StepReport DmcController::step(std::span<const double> y, std::span<const double> y_sp,
                               std::span<const double> known_offsets,
                               std::span<double> u_ctrl) noexcept {
  const auto n = static_cast<std::size_t>(n_);
  const auto p = static_cast<std::size_t>(p_);
  StepReport report;
  if (y.size() != p || y_sp.size() != p || known_offsets.size() != n || u_ctrl.size() != n) {
    if (u_ctrl.size() == n) std::copy(u_prev_.begin(), u_prev_.end(), u_ctrl.begin());
    report.status = StepStatus::held;
    return report;
  }
  // The prediction moves on one sample: ŷ(k+j) = old ŷ(k−1+j+1); the last entry is already
  // steady (every move in it is older than the settling horizon).
  const Eigen::Index stride = p_;
  for (Eigen::Index j = 0; j < static_cast<Eigen::Index>(window_); ++j) {
    prediction_.segment(j * stride, stride) = prediction_.segment((j + 1) * stride, stride);
  }
  const bool usable = finite(y) && finite(y_sp) && finite(known_offsets);
  if (!usable) {  // hold: no move, no bias update; the offsets count as unchanged
    std::copy(u_prev_.begin(), u_prev_.end(), u_ctrl.begin());
    report.status = StepStatus::held;
    return report;
  }
  const Eigen::Map<const Eigen::VectorXd> ym(y.data(), p_);
  const Eigen::Map<const Eigen::VectorXd> sp(y_sp.data(), p_);
  const Eigen::Map<const Eigen::VectorXd> offset(known_offsets.data(), n_);

  // Free response: past moves, the known offset's move, and the bias y(k) − ŷ(k|k−1).
  applied_move_ = offset - offset_prev_;  // the known part of this sample's move
  for (int j = 1; j <= P_; ++j) {
    const Eigen::Index at = static_cast<Eigen::Index>(j - 1) * stride;
    f_.segment(at, stride) = prediction_.segment(static_cast<Eigen::Index>(j) * stride, stride) +
                             ym - prediction_.head(stride);
    f_.segment(at, stride).noalias() += model_.at(j) * applied_move_;
  }
  for (int j = 0; j < P_; ++j) {
    e_.segment(static_cast<Eigen::Index>(j) * stride, stride) =
        sp - f_.segment(static_cast<Eigen::Index>(j) * stride, stride);
  }
  const Eigen::Index moves = static_cast<Eigen::Index>(M_) * n_;
  g_.head(moves).noalias() = -SuT_Q_ * e_;
  g_.tail(soft_).setZero();

  cur_ = u_prev_ + offset;  // the MV the plant receives if the controller does not move
  for (std::size_t r = 0; r < rows_.size(); ++r) {
    const Row& row = rows_[r];
    const auto m = static_cast<std::size_t>(row.index);
    double bound = 0.0;
    switch (row.kind) {
      case RowKind::move_up:
      case RowKind::move_down:
        bound = settings_.mv[m].max_move;
        break;
      case RowKind::box_up: {  // widened to what the move limits can reach by move i
        const MvSettings& mv = settings_.mv[m];
        const double reach = cur_(row.index) - (row.step + 1) * mv.max_move;
        bound = std::max(mv.max, reach) - cur_(row.index);
        break;
      }
      case RowKind::box_down: {
        const MvSettings& mv = settings_.mv[m];
        const double reach = cur_(row.index) + (row.step + 1) * mv.max_move;
        bound = cur_(row.index) - std::min(mv.min, reach);
        break;
      }
      case RowKind::cv_up:
      case RowKind::cv_down: {
        const CvSettings& v = settings_.cv[m];
        const double fj = f_(static_cast<Eigen::Index>(row.step - 1) * stride + row.index);
        const double s = sp(row.index);
        if (row.kind == RowKind::cv_up) {
          const double hi = v.zone ? std::min(v.limit_high, s + v.zone_high) : v.limit_high;
          bound = hi - fj;
        } else {
          const double lo = v.zone ? std::max(v.limit_low, s + v.zone_low) : v.limit_low;
          bound = fj - lo;
        }
        break;
      }
      case RowKind::slack:
        bound = 0.0;
        break;
    }
    b_(static_cast<Eigen::Index>(r)) = bound;
  }

  const QpResult qp = qp_->solve(g_, b_, x_);
  report.qp_iterations = qp.iterations;
  report.active_constraints = qp.active;
  if (qp.status != QpStatus::optimal) {
    // The safe fallback: the unconstrained first move, clipped into the move limits and box.
    report.status = StepStatus::qp_fallback;
    x_.head(n_).noalias() = K_ * e_;
    qp_->forget();
  }
  for (int m = 0; m < n_; ++m) {
    const MvSettings& mv = settings_.mv[static_cast<std::size_t>(m)];
    double du = x_(m);
    if (qp.status != QpStatus::optimal) {
      du = std::clamp(du, -mv.max_move, mv.max_move);
      const double lo = std::min(mv.min, cur_(m) + mv.max_move) - cur_(m);
      const double hi = std::max(mv.max, cur_(m) - mv.max_move) - cur_(m);
      du = std::clamp(du, lo, hi);
    }
    const double u = u_prev_(m) + du;
    const double applied = u + offset(m);
    const double tolerance = 1e-9 * (1.0 + std::abs(applied));
    MvStatus status = MvStatus::ok;
    if (applied <= mv.min + tolerance) {
      status = MvStatus::clamped_low;
    } else if (applied >= mv.max - tolerance) {
      status = MvStatus::clamped_high;
    } else if (std::abs(du) >= mv.max_move * (1.0 - 1e-9)) {
      status = MvStatus::move_limited;
    }
    status_[static_cast<std::size_t>(m)] = status;
    applied_move_(m) += du;  // the whole applied move: controller's plus the offset's
    u_prev_(m) = u;
    u_ctrl[static_cast<std::size_t>(m)] = u;
  }
  offset_prev_ = offset;
  // The model's prediction takes this sample's applied move.
  for (int j = 1; j <= window_; ++j) {
    prediction_.segment(static_cast<Eigen::Index>(j) * stride, stride).noalias() +=
        model_.at(j) * applied_move_;
  }
  return report;
}

}  // namespace excite::sim::control
