// SPDX-License-Identifier: MIT
// Issue 40 §1: a model file's channel names and its file name are data in every export,
// never code. Each generated script is run as exported (python3; octave with its control
// package) on names written to break out of its strings and comments, and must create no
// canary file and build the same model; a name a language cannot carry is refused naming
// its field.
//
// python-control is not packaged for Debian 12 and cannot be installed here, so the Python
// script runs against a stand-in `control` module (written below) that records what
// control.tf() was given; everything else in the script runs for real.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "host/export/formats.hpp"

namespace excite::host {
namespace {

namespace fs = std::filesystem;

struct Ran {
  int exit_code = -1;
  std::string out;
};

// `command` through the shell; every path in it is this test's own folder (no hostile text).
Ran run_shell(const std::string& command) {
  Ran r;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return r;
  std::array<char, 4096> buffer{};
  while (std::fgets(buffer.data(), buffer.size(), pipe) != nullptr) r.out += buffer.data();
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

class HostileNames : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("excite_hostile_names_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    canary_ = (dir_ / "canary").string();
  }
  void TearDown() override { fs::remove_all(dir_); }

  // 2 CVs × 2 MVs of the Wood–Berry column, named by `inputs`, `outputs`, from `source`.
  static NamedModel model(std::vector<std::string> inputs, std::vector<std::string> outputs,
                          std::string source) {
    NamedModel m;
    m.source = std::move(source);
    m.inputs = std::move(inputs);
    m.outputs = std::move(outputs);
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
    return m;
  }

  // `text` with every CANARY replaced by this test's canary path.
  std::string aimed(std::string text) const {
    for (std::size_t at; (at = text.find("CANARY")) != std::string::npos;)
      text.replace(at, 6, canary_);
    return text;
  }

  fs::path dir_;
  std::string canary_;
};

// The Python export's three ways out before issue 40: a channel name closing the embedded
// r''' string, a file name closing the docstring, and a backslash or quote at either end.
TEST_F(HostileNames, PythonScriptRunsAsDataAndBuildsTheSameModel) {
  const std::vector<std::string> inputs = {
      aimed("u''');open('CANARY','w').write('name');json.loads(r'''"), "u\\"};
  const std::vector<std::string> outputs = {aimed("y\"\"\"\nopen('CANARY','w')\n\"\"\""),
                                            "\xc3\xa9tage '\\x00' \"\\\""};
  const std::string source = aimed("m.json\"\"\"; open('CANARY','w').write('doc'); \"\"\"");
  const NamedModel m = model(inputs, outputs, source);

  fs::create_directories(dir_ / "stub");
  // The stand-in control module: tf() keeps its arguments, and prints them as JSON.
  std::ofstream(dir_ / "stub" / "control.py")
      << "import json\n"
      << "class tf:\n"
      << "    def __init__(self, num, den, inputs=None, outputs=None, name=None):\n"
      << "        self.args = {'num': num, 'den': den, 'inputs': inputs, 'outputs': outputs}\n"
      << "    def __str__(self):\n"
      << "        return 'TF ' + json.dumps(self.args)\n";
  const fs::path script = dir_ / "model.py";
  std::ofstream(script) << python_control_script(m);
  // The script as exported, then what it defined, as JSON.
  const Ran ran =
      run_shell("cd " + dir_.string() + " && PYTHONPATH=" + (dir_ / "stub").string() +
                " /usr/bin/python3 -c \"import json, runpy, sys; "
                "g = runpy.run_path(sys.argv[1], run_name='__main__'); "
                "print('DEFINED ' + json.dumps({'doc': g['__doc__'], 'inputs': g['INPUTS'], "
                "'outputs': g['OUTPUTS'], 'source': g['MODEL']['source'], "
                "'delays': g['DELAYS_MIN']}))\" " +
                script.string());
  EXPECT_FALSE(fs::exists(canary_)) << "the script wrote the canary\n" << ran.out;
  ASSERT_EQ(ran.exit_code, 0) << ran.out;

  nlohmann::json tf, defined;
  for (std::size_t at = 0; at < ran.out.size();) {
    const std::size_t end = ran.out.find('\n', at);
    const std::string line = ran.out.substr(at, end - at);
    if (line.rfind("TF ", 0) == 0) tf = nlohmann::json::parse(line.substr(3));
    if (line.rfind("DEFINED ", 0) == 0) defined = nlohmann::json::parse(line.substr(8));
    at = end == std::string::npos ? ran.out.size() : end + 1;
  }
  ASSERT_FALSE(tf.is_null()) << ran.out;
  ASSERT_FALSE(defined.is_null()) << ran.out;
  EXPECT_EQ(tf["inputs"], nlohmann::json(inputs));
  EXPECT_EQ(tf["outputs"], nlohmann::json(outputs));
  EXPECT_EQ(defined["source"], source);
  EXPECT_NE(defined["doc"].get<std::string>().find("source: " + source + ".\n"), std::string::npos)
      << defined["doc"];
  // The same model: num = K, den = [Tp 1] per element, the delays Td.
  EXPECT_EQ(tf["num"], nlohmann::json({{{12.8}, {-18.9}}, {{6.6}, {-19.4}}}));
  EXPECT_EQ(tf["den"], nlohmann::json({{{16.7, 1.0}, {21.0, 1.0}}, {{10.9, 1.0}, {14.4, 1.0}}}));
  EXPECT_EQ(defined["delays"], nlohmann::json({{1.0, 3.0}, {7.0, 3.0}}));
}

// The MATLAB export's way out before issue 40: a newline in the file name ends the
// `% source:` comment and starts a statement. Quotes in names are doubled and stay names.
TEST_F(HostileNames, MatlabScriptRunsAsDataUnderOctaveAndBuildsTheSameModel) {
  if (!fs::exists("/usr/bin/octave"))
    GTEST_SKIP() << "octave is not installed (apt-get install octave octave-control)";
  const std::vector<std::string> inputs = {aimed("u'); fclose(fopen('CANARY', 'w')); x = ('"),
                                           "u '' % ... \"\\n\" #{"};
  const std::vector<std::string> outputs = {"y1", "y2 ''"};
  const std::string source =
      aimed("m.json\nfclose(fopen('CANARY', 'w'));\r\nfclose(fopen('CANARY', 'w')); %");
  const NamedModel m = model(inputs, outputs, source);
  const fs::path script = dir_ / "model.m";
  std::ofstream(script) << matlab_script(m) << "printf('GAIN %.17g\\n', dcgain(G)');\n"
                        << "names = G.inname; printf('IN %s\\n', names{:});\n"
                        << "names = G.outname; printf('OUT %s\\n', names{:});\n"
                        << "printf('DELAY %.17g\\n', (input_delay_min + io_delay_min)');\n";
  const Ran ran =
      run_shell("cd " + dir_.string() + " && octave --no-gui --norc -q " + script.string());
  EXPECT_FALSE(fs::exists(canary_)) << "the script wrote the canary\n" << ran.out;
  ASSERT_EQ(ran.exit_code, 0) << ran.out;
  std::vector<double> gains, delays;
  std::vector<std::string> in, out;
  for (std::size_t at = 0; at < ran.out.size();) {
    const std::size_t end = ran.out.find('\n', at);
    const std::string line = ran.out.substr(at, end - at);
    if (line.rfind("GAIN ", 0) == 0) gains.push_back(std::stod(line.substr(5)));
    if (line.rfind("DELAY ", 0) == 0) delays.push_back(std::stod(line.substr(6)));
    if (line.rfind("IN ", 0) == 0) in.push_back(line.substr(3));
    if (line.rfind("OUT ", 0) == 0) out.push_back(line.substr(4));
    at = end == std::string::npos ? ran.out.size() : end + 1;
  }
  EXPECT_EQ(in, inputs) << ran.out;
  EXPECT_EQ(out, outputs) << ran.out;
  const std::vector<double> expected_gains = {12.8, -18.9, 6.6, -19.4};  // row-major
  ASSERT_EQ(gains.size(), expected_gains.size()) << ran.out;
  for (std::size_t k = 0; k < gains.size(); ++k)  // dcgain evaluates num/den: a rounding off
    EXPECT_NEAR(gains[k], expected_gains[k], 1e-12 * std::abs(expected_gains[k])) << ran.out;
  EXPECT_EQ(delays, (std::vector<double>{1.0, 3.0, 7.0, 3.0})) << ran.out;
}

// What a MATLAB char literal cannot hold is refused, naming the field; what no export can
// carry (bytes that are not UTF-8) is refused by every format, naming the field.
TEST_F(HostileNames, NamesALanguageCannotCarryAreRefusedNamingTheField) {
  const auto refusal = [](auto&& write) {
    try {
      (void)write();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("(not refused)");
  };
  const NamedModel newline = model({"u1", "u2\nsystem('x')"}, {"y1", "y2"}, "m.json");
  const std::string matlab = refusal([&] { return matlab_script(newline); });
  EXPECT_NE(matlab.find("m.json: inputs[1] = \"u2\\x0asystem('x')\", expected a name without "
                        "control characters"),
            std::string::npos)
      << matlab;
  // Python and JSON have escapes for it: the name is kept.
  EXPECT_NE(python_control_script(newline).find("u2\\\\nsystem"), std::string::npos);

  const NamedModel latin1 = model({"u1", "u2"},
                                  {"y1",
                                   "d\xe9"
                                   "bit"},
                                  "m.json");
  for (const auto& write : std::vector<std::string (*)(const NamedModel&)>{
           matlab_script, python_control_script, transfer_json,
           [](const NamedModel& x) { return step_csv(x, 5); }}) {
    const std::string what = refusal([&] { return write(latin1); });
    EXPECT_NE(what.find("m.json: outputs[1] = \"d\\xe9bit\" (byte 1), expected UTF-8 text"),
              std::string::npos)
        << what;
  }
  const NamedModel bad_source = model({"u1", "u2"}, {"y1", "y2"}, "m\xff.json");
  EXPECT_NE(refusal([&] {
              return python_control_script(bad_source);
            }).find("source (the model file's name) = \"m\\xff.json\" (byte 1), expected UTF-8"),
            std::string::npos);
}

// The step table's comment carries the file name escaped: a newline in it starts no row.
TEST_F(HostileNames, StepTableSourceLineIsOneComment) {
  const std::string csv = step_csv(model({"u1", "u2"}, {"y1", "y2"}, "m.json\n1,2,3,4,5,6"), 3);
  EXPECT_NE(csv.find("# source: m.json\\x0a1,2,3,4,5,6\n"), std::string::npos) << csv;
  std::size_t rows = 0;
  for (std::size_t at = 0; (at = csv.find('\n', at)) != std::string::npos; ++at) {
    if (at + 1 < csv.size() && csv[at + 1] != '#') ++rows;
  }
  EXPECT_EQ(rows, 1U + 3U) << csv;  // the column names and k = 1 … 3
}

}  // namespace
}  // namespace excite::host
