// SPDX-License-Identifier: MIT
// Models out (host/export): the DMC step table against the analytic step response, the
// MATLAB/Octave and python-control scripts read back (and run where the tool is installed),
// the JSON round trip, the refusal of unknown elements, and a model as a simulated plant.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <nlohmann/json.hpp>

#include <algorithm>
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
  const std::vector<ElementModel> p = {{2.5, 1.3, 20.0, 5.0},  {-1.5, 4.75, 12.0, 12.0},
                                       {0.8, 0.0, 7.0, 0.0},   {1.2, 2.5, 0.0, 0.0},
                                       {-0.3, 0.4, 30.0, 2.0}, {4.09, 10.2, 33.0, 8.3}};
  for (const ElementModel& e : p) {
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
      const ElementModel& p = m.model.elements[e].value;
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
    Eigen::VectorXd y(u.size());
    simulate(discretise(e.value, 1.0), {u.data(), 121}, {y.data(), 121});
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
    const ElementModel& a = m.model.elements[e].value;
    const ElementModel& b = back.model.elements[e].value;
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
    const ElementModel& p = m.model.elements[e].value;
    EXPECT_EQ(num[e], p.gain);
    EXPECT_NEAR(input_delay[e % 3] + io_delay[e], p.delay_min, 1e-15);
  }
  EXPECT_EQ(input_delay, (std::vector<double>{1.3, 0.4, 0.0}));
  EXPECT_NE(script.find("'InputName', input_names"), std::string::npos);
  EXPECT_NE(script.find("input_names = {'reflux L', 'boil-up V', 'feed F'};"), std::string::npos);
  EXPECT_NE(script.find("'TimeUnit', 'minutes'"), std::string::npos);
}

// The step table (step_csv, what `excite export --format step-csv` writes) as numbers:
// table[k - 1][e] = s_e(k T), e row-major over CV x MV, k = 1..horizon.
std::vector<std::vector<double>> step_table(const NamedModel& m, int horizon) {
  const std::vector<std::string> lines = lines_of(step_csv(m, horizon));
  std::vector<std::vector<double>> table;
  for (std::size_t l = 6; l < lines.size(); ++l) {
    std::vector<double> row = numbers_in(lines[l]);
    row.erase(row.begin(), row.begin() + 2);  // k, t_min
    table.push_back(row);
  }
  return table;
}

// Compares the printed step responses ("NAME o i s(T) s(2T) …" lines, 1-based o, i) with the
// step table to `tolerance`, every element once; returns the largest difference.
double compare_steps(const std::string& out, const std::string& name, const NamedModel& m,
                     const std::vector<std::vector<double>>& table, double tolerance) {
  double largest = 0.0;
  std::size_t elements = 0;
  for (const std::string& line : lines_of(out)) {
    if (line.rfind(name + " ", 0) != 0) continue;
    const std::vector<double> v = numbers_in(line.substr(name.size()));
    EXPECT_EQ(v.size(), 2 + table.size()) << line.substr(0, 80);
    if (v.size() != 2 + table.size()) continue;
    const auto e = static_cast<std::size_t>((v[0] - 1) * m.model.inputs + (v[1] - 1));
    for (std::size_t k = 0; k < table.size(); ++k) {
      EXPECT_NEAR(v[2 + k], table[k][e], tolerance) << name << " element " << e << " k " << k + 1;
      largest = std::max(largest, std::abs(v[2 + k] - table[k][e]));
    }
    ++elements;
  }
  EXPECT_EQ(elements, m.model.elements.size()) << out.substr(0, 2000);
  return largest;
}

// The MATLAB script run under Octave with the control package (toolchain/packages.txt:
// octave, octave-control; a skip is unexpected, tests/skips): dcgain(G) is the model's K,
// the names are Octave's inname/outname, the delays input_delay_min + io_delay_min are each
// element's T_d, and Octave's own step response of G (step(), exact ZOH on a 0.05-min grid,
// every delay here a multiple of it) delayed by those delays equals the step table to 1e-6.
TEST(MatlabScript, RunsUnderOctaveWithTheControlPackage) {
  if (!std::filesystem::exists("/usr/bin/octave"))
    GTEST_SKIP() << "octave is not installed (apt-get install octave octave-control)";
  const NamedModel m = known_model();
  const int horizon = settling_samples(m.model);
  const auto path = temp_file("model.m");
  std::ofstream(path) << matlab_script(m) << "printf('%.12g\\n', dcgain(G)');\nnames = G.inname;\n"
                      << "printf('%s|', names{:});\nnames = G.outname;\n"
                      << "printf('\\n'); printf('%s|', names{:}); printf('\\n');\n"
                      << "dt = 0.05; H = " << horizon << "; [y, tt] = step(G, 0:dt:H);\n"
                      << "for o = 1:rows(num)\n  for i = 1:columns(num)\n"
                      << "    td = input_delay_min(i) + io_delay_min(o, i);\n"
                      << "    printf('delay %d %d %.17g\\n', o, i, td);\n"
                      << "    s = zeros(1, H);\n    for k = 1:H\n      at = (k - td) / dt;\n"
                      << "      if at > 0, s(k) = y(round(at) + 1, o, i); end\n    end\n"
                      << "    printf('octave %d %d', o, i); printf(' %.17g', s); printf('\\n');\n"
                      << "  end\nend\n";
  const ProcessResult r = run("octave --no-gui --norc -q " + path.string());
  std::filesystem::remove(path);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const std::vector<std::string> lines = lines_of(r.out);
  std::vector<double> gains;
  for (std::size_t l = 0; l < 6 && l < lines.size(); ++l) gains.push_back(std::stod(lines[l]));
  EXPECT_EQ(gains, (std::vector<double>{2.5, -1.5, 0.8, 1.2, -0.3, 4.09})) << r.out;
  EXPECT_NE(r.out.find("reflux L|boil-up V|feed F|"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("xD|xB|"), std::string::npos) << r.out;
  std::size_t delays = 0;
  for (const std::string& line : lines) {
    if (line.rfind("delay ", 0) != 0) continue;
    const std::vector<double> v = numbers_in(line.substr(6));
    ASSERT_EQ(v.size(), 3U) << line;
    const auto e = static_cast<std::size_t>((v[0] - 1) * 3 + (v[1] - 1));
    EXPECT_NEAR(v[2], m.model.elements[e].value.delay_min, 1e-12) << line;
    ++delays;
  }
  EXPECT_EQ(delays, 6U) << r.out;
  const double largest = compare_steps(r.out, "octave", m, step_table(m, horizon), 1e-6);
  std::printf("Octave step responses against the step table: largest difference %.3g\n", largest);
}

// The python-control script, without python-control (Debian 12 does not package it, so the
// script's `G = control.tf(…)` is never run: for that line this is a syntax check only).
// What is checked for real: the script compiles (/usr/bin/python3, ast), its embedded model
// is transfer_json()'s, and the script's own data (every top-level assignment that does not
// use `control`, executed: MODEL, INPUTS, ELEMENTS, DELAYS_MIN) driven through scipy.signal's
// step response of each num/den (python3-scipy), delayed by DELAYS_MIN, is the step table to
// 1e-6.
TEST(PythonControlScript, CompilesAndItsEmbeddedModelStepsAsTheStepTableUnderScipy) {
  const NamedModel m = known_model();
  const std::string script = python_control_script(m);
  const auto begin = script.find("json.loads('''");
  const auto end = script.find("''')", begin);
  ASSERT_NE(begin, std::string::npos);
  ASSERT_NE(end, std::string::npos);
  std::string body;  // the literal's text with Python's \\ and \' read back
  for (std::size_t k = begin + 14; k < end; ++k) {
    if (script[k] == '\\') ++k;
    body += script[k];
  }
  const auto embedded = nlohmann::json::parse(body);
  EXPECT_EQ(embedded, nlohmann::json::parse(transfer_json(m)));
  const NamedModel back = read_transfer_json(embedded.dump(), "embedded");
  EXPECT_EQ(back.model.element(1, 2).value.tau2_min, 8.3);
  for (const char* needle :
       {"G = control.tf(", "inputs=INPUTS", "def with_pade(order=3):", "DELAYS_MIN = "}) {
    EXPECT_NE(script.find(needle), std::string::npos) << needle;
  }
  if (!std::filesystem::exists("/usr/bin/python3")) GTEST_SKIP() << "no /usr/bin/python3";
  const int horizon = settling_samples(m.model);
  const auto path = temp_file("model.py");
  const auto checker = temp_file("check_model.py");
  std::ofstream(path) << script;
  std::ofstream(checker)
      << "import ast, sys\nimport numpy as np\nfrom scipy import signal\n"
      << "tree = ast.parse(open(sys.argv[1]).read())\nspace = {}\n"
      << "def uses_control(node):\n"
      << "    return any(isinstance(n, ast.Name) and n.id == 'control' or\n"
      << "               isinstance(n, ast.alias) and n.name == 'control' for n in "
         "ast.walk(node))\n"
      << "for node in tree.body:\n"
      << "    if isinstance(node, (ast.Assign, ast.Import)) and not uses_control(node):\n"
      << "        exec(compile(ast.Module([node], []), sys.argv[1], 'exec'), space)\n"
      << "H = int(sys.argv[2])\n"
      << "for o, row in enumerate(space['ELEMENTS']):\n"
      << "    for i, e in enumerate(row):\n"
      << "        t = np.arange(1, H + 1) - space['DELAYS_MIN'][o][i]\n"
      << "        s = np.zeros(H)\n"
      << "        on = t > 0\n"
      << "        if len(e['den']) == 1:\n"
      << "            s[on] = e['num'][0] / e['den'][0]\n"
      << "        else:\n"
      << "            T = np.concatenate(([0.0], t[on]))\n"
      << "            s[on] = signal.step(signal.lti(e['num'], e['den']), T=T)[1][1:]\n"
      << "        print('scipy', o + 1, i + 1, ' '.join(repr(float(x)) for x in s))\n"
      << "print('inputs', '|'.join(space['INPUTS']))\n";
  const ProcessResult ran = run("/usr/bin/python3 " + checker.string() + " " + path.string() + " " +
                                std::to_string(horizon));
  std::filesystem::remove(path);
  std::filesystem::remove(checker);
  ASSERT_EQ(ran.exit_code, 0) << ran.out;
  EXPECT_NE(ran.out.find("inputs reflux L|boil-up V|feed F"), std::string::npos) << ran.out;
  const double largest = compare_steps(ran.out, "scipy", m, step_table(m, horizon), 1e-6);
  std::printf("scipy step responses against the step table: largest difference %.3g\n", largest);
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
  for (const ElementModel& p : std::vector<ElementModel>{{12.8, 1.0, 16.7, 0.0},
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
