// SPDX-License-Identifier: MIT
#include "sim/control/make_controller.hpp"

#include <cmath>

#include "base/config/document.hpp"
#include "base/config/error.hpp"
#include "sim/control/dmc.hpp"
#include "sim/control/integral_controllability.hpp"
#include "sim/control/pi.hpp"
#include "sim/control/step_model.hpp"

namespace excite::sim::control {
namespace {

[[noreturn]] void refuse(const ControllerFile& file, std::string field, std::string value,
                         std::string expected) {
  throw config::Error(file.source, config::Position{}, std::move(field), std::move(value),
                      std::move(expected));
}

// Runs `make`, giving every refusal the file's name.
template <typename Make>
auto in_file(const ControllerFile& file, Make make) {
  try {
    return make();
  } catch (const config::Error& e) {
    throw e.with_source(file.source);
  } catch (const std::invalid_argument& e) {
    throw config::Error::text(file.source, config::Position{}, e.what());
  }
}

void check_count(const ControllerFile& file, const char* key, bool given, std::size_t entries,
                 int expected, const char* what) {
  if (given && entries != static_cast<std::size_t>(expected)) {
    refuse(file, key, std::to_string(entries) + " entries",
           std::to_string(expected) + " (one per " + what + " of the model, in its order)");
  }
}

}  // namespace

std::unique_ptr<Plant> load_model(const ControllerFile& file) {
  if (!file.model.model_file.empty()) {
    refuse(file, "model.model_file", "\"" + file.model.model_file + "\"",
           "a plant name or plant file here: a model of excite identify is read by excite "
           "(host/export), which passes its plant to make_controller");
  }
  return in_file(file, [&] { return make_plant(file.model.plant); });
}

std::unique_ptr<Controller> make_controller(const ControllerFile& file, Plant& model,
                                            const Eigen::MatrixXd* plant_gain) {
  const int n = model.inputs();
  const int p = model.outputs();
  check_count(file, "mv", file.mv_given, file.dmc.mv.size(), n, "input (MV)");
  std::vector<MvSettings> mv =
      file.mv_given ? file.dmc.mv : std::vector<MvSettings>(static_cast<std::size_t>(n));
  const std::string model_name = file.model.plant.empty() ? model.name() : file.model.plant;
  if (file.kind == ControllerKind::dmc) {
    check_count(file, "cv", file.cv_given, file.dmc.cv.size(), p, "output (CV)");
    if (plant_gain != nullptr) {
      if (plant_gain->rows() != p || plant_gain->cols() != n) {
        refuse(file, "model",
               "\"" + model_name + "\" (" + std::to_string(p) + "×" + std::to_string(n) + ")",
               "the plant's size, " + std::to_string(plant_gain->rows()) + "×" +
                   std::to_string(plant_gain->cols()) + " (outputs × inputs)");
      }
      const config::Check ic =
          check_integral_controllability(model.static_gain(), *plant_gain, model_name);
      if (!ic.ok()) throw config::Error(ic).with_source(file.source);
    }
    DmcSettings settings = file.dmc;
    settings.mv = mv;
    if (!file.cv_given) settings.cv.assign(static_cast<std::size_t>(p), CvSettings{});
    return in_file(file, [&]() -> std::unique_ptr<Controller> {
      StepModelOptions options;
      options.probe_step = file.model.probe_step;
      StepModel s =
          step_model(model, file.sample_time_min, options).delayed(file.model.delay_samples);
      return std::make_unique<DmcController>(std::move(s), std::move(settings));
    });
  }
  const Eigen::MatrixXd gain = model.static_gain();
  for (std::size_t i = 0; i < file.pairing.size(); ++i) {
    const PiLoop& l = file.pairing[i];
    if (l.cv >= p) {
      refuse(file, "pairing[" + std::to_string(i) + "].cv", std::to_string(l.cv + 1),
             "a CV 1.." + std::to_string(p) + " of the model");
    }
    if (l.mv >= n) {
      refuse(file, "pairing[" + std::to_string(i) + "].mv", std::to_string(l.mv + 1),
             "an MV 1.." + std::to_string(n) + " of the model");
    }
    const double g = gain(l.cv, l.mv);
    if (!(g * l.gain > 0.0)) {
      refuse(file, "pairing[" + std::to_string(i) + "].kc", config::format_number(l.gain),
             "a gain of the sign of the paired G(0) element (" + config::format_number(g) +
                 "): the other sign is positive feedback");
    }
  }
  PiSettings settings;
  settings.sample_time_min = file.sample_time_min;
  settings.inputs = n;
  settings.outputs = p;
  settings.loops = file.pairing;
  settings.mv = mv;
  return in_file(file, [&]() -> std::unique_ptr<Controller> {
    return std::make_unique<PiController>(std::move(settings));
  });
}

}  // namespace excite::sim::control
