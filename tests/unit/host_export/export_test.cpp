// SPDX-License-Identifier: MIT
// Models out (host/export): the DMC step table against the analytic step response, the
// MATLAB/Octave and python-control scripts read back (and run where the tool is installed),
// the JSON round trip, the refusal of unknown elements, and a model as a simulated plant.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "host/export/formats.hpp"
#include "host/export/model_plant.hpp"
#include "host/export/step_response.hpp"
#include "sim/lti/sopdt.hpp"

namespace excite::host {
namespace {

// The analytic unit-step response of K e^{−s Td}/((T1 s + 1)(T2 s + 1)), written out here
// independently of host/export (distinct, equal and single time constants).
double analytic_step(double K, double Td, double T1, double T2, double t) {
  const double tau = t - Td;
  if (tau <= 0.0) return 0.0;
  if (T1 == 0.0 && T2 == 0.0) return K;
  if (T2 == 0.0) return K * (1.0 - std::exp(-tau / T1));
  if (T1 == T2) return K * (1.0 - (1.0 + tau / T1) * std::exp(-tau / T1));
  return K * (1.0 + (T2 * std::exp(-tau / T2) - T1 * std::exp(-tau / T1)) / (T1 - T2));
}

// 2 CVs × 3 MVs, every kind of element, fractional delays.
NamedModel known_model() {
  NamedModel m;
  m.source = "known.json";
  m.inputs = {"reflux L", "boil-up V", "feed F"};
  m.outputs = {"xD", "xB"};
  m.model.inputs = 3;
  m.model.outputs = 2;
  m.model.sample_time_min = 1.0;
  const std::vector<TwoPoleDelay> p = {{2.5, 1.3, 20.0, 5.0},  {-1.5, 4.75, 12.0, 12.0},
                                       {0.8, 0.0, 7.0, 0.0},   {1.2, 2.5, 0.0, 0.0},
                                       {-0.3, 0.4, 30.0, 2.0}, {4.09, 10.2, 33.0, 8.3}};
  for (const TwoPoleDelay& e : p) {
    ElementEstimate est;
    est.value = e;
    m.model.elements.push_back(est);
  }
  return m;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// Every number in `text`, in order (identifiers skipped). No std::regex: GCC 12 warns
// inside <regex> under the asan preset's -Werror.
std::vector<double> numbers_in(const std::string& text) {
  std::vector<double> v;
  const char* p = text.c_str();
  while (*p != '\0') {
    if (std::isalpha(static_cast<unsigned char>(*p)) != 0 || *p == '_') {
      while (std::isalnum(static_cast<unsigned char>(*p)) != 0 || *p == '_') ++p;
      continue;
    }
    char* end = nullptr;
    const double x = std::strtod(p, &end);
    if (end != p && (std::isdigit(static_cast<unsigned char>(*p)) != 0 || *p == '-' || *p == '+' ||
                     *p == '.')) {
      v.push_back(x);
      p = end;
    } else {
      ++p;
    }
  }
  return v;
}

struct ProcessResult {
  int exit_code = -1;
  std::string out;
};
ProcessResult run(const std::string& command) {
  ProcessResult r;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return r;
  std::array<char, 4096> buffer{};
  while (std::fgets(buffer.data(), buffer.size(), pipe) != nullptr) r.out += buffer.data();
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

std::filesystem::path temp_file(const std::string& name) {
  return std::filesystem::temp_directory_path() /
         ("excite_export_" + std::to_string(::getpid()) + "_" + name);
}

TEST(StepCsv, CoefficientsEqualTheAnalyticStepResponseWithDelays) {
  const NamedModel m = known_model();
  const std::vector<std::string> lines = lines_of(step_csv(m, 200));
  ASSERT_EQ(lines.size(), 6U + 200U);  // 5 '#' lines, the column names, 200 rows
  EXPECT_EQ(lines[0], "# excite step response v1");
  EXPECT_EQ(lines[2], "# sample_time_min: 1");
  EXPECT_EQ(lines[3], "# horizon: 200 samples (200 min)");
  EXPECT_EQ(lines[5],
            "k,t_min,xD <- reflux L,xD <- boil-up V,xD <- feed F,xB <- reflux L,xB <- boil-up "
            "V,xB <- feed F");
  double largest_error = 0.0;
  for (int k = 1; k <= 200; ++k) {
    const std::vector<double> row = numbers_in(lines[static_cast<std::size_t>(5 + k)]);
    ASSERT_EQ(row.size(), 8U) << lines[static_cast<std::size_t>(5 + k)];
    EXPECT_EQ(row[0], k);
    EXPECT_EQ(row[1], k * 1.0);
    for (std::size_t e = 0; e < 6; ++e) {
      const TwoPoleDelay& p = m.model.elements[e].value;
      const double expected = analytic_step(p.gain, p.delay_min, p.tau1_min, p.tau2_min, k);
      EXPECT_NEAR(row[2 + e], expected, 1e-9) << "k " << k << " element " << e;
      largest_error = std::max(largest_error, std::abs(row[2 + e] - expected));
    }
  }
  EXPECT_LT(largest_error, 1e-9);
  // A delay of 10.2 min: s_10 = 0, s_11 > 0 (the step shows 0.8 min after t = 10.2).
  EXPECT_EQ(numbers_in(lines[5 + 10])[7], 0.0);
  EXPECT_GT(numbers_in(lines[5 + 11])[7], 0.0);
}

// The same coefficients as the plants' own exact ZOH simulation (sim/lti) of a unit step.
TEST(StepCsv, CoefficientsEqualTheSimulatedUnitStep) {
  const NamedModel m = known_model();
  const Eigen::VectorXd u = Eigen::VectorXd::Ones(121);
  for (const ElementEstimate& e : m.model.elements) {
    const Eigen::VectorXd y = sim::simulate_sopdt(e.value, 1.0, u);
    for (int k = 1; k <= 120; ++k) EXPECT_NEAR(step_response(e.value, k), y(k), 1e-9) << k;
  }
}

TEST(StepCsv, DefaultHorizonCoversTheSlowestElement) {
  // 10.2 + 7 (33 + 8.3) = 299.3 min → 300 samples of 1 min.
  EXPECT_EQ(settling_samples(known_model().model), 300);
}

TEST(Export, ModelWithAnUnknownElementIsRefusedNamingIt) {
  NamedModel m = known_model();
  ElementEstimate& e = m.model.element(1, 2);
  e.value = {NAN, NAN, NAN, NAN};
  e.status = ElementStatus::input_collinear;
  e.reason = "feed F is a linear combination of the other inputs";
  try {
    (void)step_csv(m, 10);
    FAIL() << "expected a refusal";
  } catch (const std::invalid_argument& error) {
    const std::string what = error.what();
    EXPECT_NE(what.find("outputs[1].elements[2] (xB <- feed F)"), std::string::npos) << what;
    EXPECT_NE(what.find("input_collinear"), std::string::npos) << what;
  }
  EXPECT_THROW((void)matlab_script(m), std::invalid_argument);
  EXPECT_THROW((void)python_control_script(m), std::invalid_argument);
  EXPECT_THROW((void)transfer_json(m), std::invalid_argument);
  EXPECT_THROW((void)step_csv(known_model(), 0), std::invalid_argument);
}

TEST(TransferJson, RoundTripsEveryParameterExactly) {
  NamedModel m = known_model();
  m.model.element(0, 0).value.gain = 1.0 / 3.0;  // not exact in decimal
  m.model.element(1, 1).status = ElementStatus::weak_gain;
  const std::string text = transfer_json(m);
  const NamedModel back = read_transfer_json(text, "back.json");
  EXPECT_EQ(back.inputs, m.inputs);
  EXPECT_EQ(back.outputs, m.outputs);
  EXPECT_EQ(back.model.sample_time_min, m.model.sample_time_min);
  ASSERT_EQ(back.model.elements.size(), m.model.elements.size());
  for (std::size_t e = 0; e < m.model.elements.size(); ++e) {
    const TwoPoleDelay& a = m.model.elements[e].value;
    const TwoPoleDelay& b = back.model.elements[e].value;
    EXPECT_EQ(a.gain, b.gain);
    EXPECT_EQ(a.delay_min, b.delay_min);
    EXPECT_EQ(a.tau1_min, b.tau1_min);
    EXPECT_EQ(a.tau2_min, b.tau2_min);
    EXPECT_EQ(back.model.elements[e].status, m.model.elements[e].status);
  }
  // num/den in descending powers of s: (20s + 1)(5s + 1) = 100 s² + 25 s + 1.
  const auto j = nlohmann::json::parse(text);
  EXPECT_EQ(j["elements"][0][1]["den"], nlohmann::json({144.0, 24.0, 1.0}));
  EXPECT_EQ(j["elements"][0][2]["den"], nlohmann::json({7.0, 1.0}));
  EXPECT_EQ(j["elements"][1][0]["den"], nlohmann::json({1.0}));
  EXPECT_THROW((void)read_transfer_json("{\"format\":\"other\"}", "x.json"), std::invalid_argument);
}

// The MATLAB script read back by a parser: num, den and the delays are the model's, the
// input delay is each MV's smallest delay and InputDelay + IODelay is every element's.
TEST(MatlabScript, ParsesBackToTheModel) {
  const NamedModel m = known_model();
  const std::string script = matlab_script(m);
  const auto assigned = [&](const std::string& name) {
    const std::string head = "\n" + name + " = ";
    const std::size_t at = script.find(head);
    const std::size_t end = at == std::string::npos ? at : script.find(";\n", at + head.size());
    EXPECT_NE(end, std::string::npos) << name << "\n" << script;
    if (end == std::string::npos) return std::string();
    const std::string value = script.substr(at + head.size(), end - at - head.size());
    EXPECT_EQ(value.find('\n'), std::string::npos) << name << "\n" << script;
    return value;
  };
  const std::vector<double> num = numbers_in(assigned("num"));
  const std::vector<double> den = numbers_in(assigned("den"));
  const std::vector<double> input_delay = numbers_in(assigned("input_delay_min"));
  const std::vector<double> io_delay = numbers_in(assigned("io_delay_min"));
  ASSERT_EQ(num.size(), 6U);
  ASSERT_EQ(input_delay.size(), 3U);
  ASSERT_EQ(io_delay.size(), 6U);
  // den: [T1T2 T1+T2 1] | [T 1] | [1] per element, row-major.
  const std::vector<double> expected_den = {100, 25, 1,  144, 24,         1,          7, 1,
                                            1,   60, 32, 1,   33.0 * 8.3, 33.0 + 8.3, 1};
  EXPECT_EQ(den, expected_den);
  for (std::size_t e = 0; e < 6; ++e) {
    const TwoPoleDelay& p = m.model.elements[e].value;
    EXPECT_EQ(num[e], p.gain);
    EXPECT_NEAR(input_delay[e % 3] + io_delay[e], p.delay_min, 1e-15);
  }
  EXPECT_EQ(input_delay, (std::vector<double>{1.3, 0.4, 0.0}));
  EXPECT_NE(script.find("'InputName', input_names"), std::string::npos);
  EXPECT_NE(script.find("input_names = {'reflux L', 'boil-up V', 'feed F'};"), std::string::npos);
  EXPECT_NE(script.find("'TimeUnit', 'minutes'"), std::string::npos);
}

// Run under Octave with the control package where it is installed (not a CI dependency:
// host/README.md): G's static gain is the model's K and the names are set.
TEST(MatlabScript, RunsUnderOctaveWithTheControlPackage) {
  if (!std::filesystem::exists("/usr/bin/octave"))
    GTEST_SKIP() << "octave is not installed (apt-get install octave octave-control)";
  const auto path = temp_file("model.m");
  std::ofstream(path) << matlab_script(known_model())
                      << "printf('%.12g\\n', dcgain(G)');\nnames = G.inname;\n"
                      << "printf('%s|', names{:});\nnames = G.outname;\n"
                      << "printf('\\n'); printf('%s|', names{:});\n";
  const ProcessResult r = run("octave --no-gui --norc -q " + path.string());
  std::filesystem::remove(path);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const std::vector<std::string> lines = lines_of(r.out);
  std::vector<double> gains;
  for (std::size_t l = 0; l < 6 && l < lines.size(); ++l) gains.push_back(std::stod(lines[l]));
  EXPECT_EQ(gains, (std::vector<double>{2.5, -1.5, 0.8, 1.2, -0.3, 4.09})) << r.out;
  EXPECT_NE(r.out.find("reflux L|boil-up V|feed F|"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("xD|xB|"), std::string::npos) << r.out;
}

// The python-control script: valid Python (compiled by the system's python3), and the model
// it embeds is transfer_json()'s. Run with python-control where it is installed.
TEST(PythonControlScript, IsValidPythonEmbeddingTheModel) {
  const NamedModel m = known_model();
  const std::string script = python_control_script(m);
  const auto begin = script.find("json.loads(r'''");
  const auto end = script.find("''')", begin);
  ASSERT_NE(begin, std::string::npos);
  ASSERT_NE(end, std::string::npos);
  const auto embedded = nlohmann::json::parse(script.substr(begin + 15, end - begin - 15));
  EXPECT_EQ(embedded, nlohmann::json::parse(transfer_json(m)));
  const NamedModel back = read_transfer_json(embedded.dump(), "embedded");
  EXPECT_EQ(back.model.element(1, 2).value.tau2_min, 8.3);
  for (const char* needle :
       {"G = control.tf(", "inputs=INPUTS", "def with_pade(order=3):", "DELAYS_MIN = "}) {
    EXPECT_NE(script.find(needle), std::string::npos) << needle;
  }
  if (!std::filesystem::exists("/usr/bin/python3")) GTEST_SKIP() << "no /usr/bin/python3";
  const auto path = temp_file("model.py");
  std::ofstream(path) << script;
  const ProcessResult compiled =
      run("/usr/bin/python3 -c \"import ast,sys; ast.parse(open(sys.argv[1]).read())\" " +
          path.string());
  EXPECT_EQ(compiled.exit_code, 0) << compiled.out;
  if (run("/usr/bin/python3 -c 'import control'").exit_code == 0) {
    const ProcessResult ran = run("/usr/bin/python3 " + path.string());
    EXPECT_EQ(ran.exit_code, 0) << ran.out;
  }
  std::filesystem::remove(path);
}

// A model as a plant: the library's Wood–Berry column (every element first order with a
// delay, so exactly of form (6.1.1)) and the model of its elements give the same run.
TEST(ModelPlant, ReproducesThePlantTheModelEquals) {
  NamedModel m;
  m.source = "woodberry-model.json";
  m.inputs = {"R", "S"};
  m.outputs = {"xD", "xB"};
  m.model.inputs = m.model.outputs = 2;
  m.model.sample_time_min = 1.0;
  for (const TwoPoleDelay& p : std::vector<TwoPoleDelay>{{12.8, 1.0, 16.7, 0.0},
                                                         {-18.9, 3.0, 21.0, 0.0},
                                                         {6.6, 7.0, 10.9, 0.0},
                                                         {-19.4, 3.0, 14.4, 0.0}}) {
    ElementEstimate e;
    e.value = p;
    m.model.elements.push_back(e);
  }
  const auto model = plant_from_model(m);
  const auto plant = sim::make_plant("woodberry2x2");
  EXPECT_EQ(model->input_names(), m.inputs);
  EXPECT_EQ(model->output_names(), m.outputs);
  Eigen::MatrixXd U(400, 2);
  for (Eigen::Index k = 0; k < U.rows(); ++k) {
    U(k, 0) = (k / 17) % 2 ? 1.0 : -1.0;
    U(k, 1) = (k / 29) % 3 == 0 ? 0.5 : -0.25;
  }
  const Eigen::MatrixXd expected = plant->simulate(U, 1.0);
  const Eigen::MatrixXd got = model->simulate(U, 1.0);
  EXPECT_LT((got - expected).cwiseAbs().maxCoeff(), 1e-9 * expected.cwiseAbs().maxCoeff());
  EXPECT_TRUE(model->static_gain().isApprox(plant->static_gain(), 1e-14));
}

}  // namespace
}  // namespace excite::host
