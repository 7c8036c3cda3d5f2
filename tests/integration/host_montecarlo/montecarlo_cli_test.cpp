// SPDX-License-Identifier: MIT
// `excite montecarlo` run as a process, as an engineer or a batch script would: the summary
// and its table, a real SIGINT and the resumed run, shards and thread counts giving the same
// bytes, and merge naming a missing or duplicated shard.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "../host_cli/cli_process.hpp"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using excite_cli_test::bytes_of;
using excite_cli_test::excite;
using MonteCarlo = excite_cli_test::ExciteCli;

// A small run: woodberry2x2 (945-sample experiments), a few designs and seeds.
std::string run_of(int seeds) {
  return "montecarlo --plant woodberry2x2 --designs stepSeq,prbsUnc,prbsSimDir --seeds " +
         std::to_string(seeds) + " --first-seed 3 --length-step 25";
}
const std::string kRun = run_of(4);

std::size_t units_in(const fs::path& dir) {
  if (!fs::exists(dir / "units")) return 0;
  std::size_t n = 0;
  for (const auto& entry : fs::recursive_directory_iterator(dir / "units"))
    n += entry.path().extension() == ".json" ? 1U : 0U;
  return n;
}

}  // namespace

TEST_F(MonteCarlo, WritesTheSummaryWithSpreadsSharesAndT90AndPrintsTheTable) {
  const auto r = excite(kRun + " --threads 2 -o " + path("mc"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const nlohmann::json s = nlohmann::json::parse(bytes_of(path("mc") + "/summary.json"));
  ASSERT_EQ(s["designs"].size(), 3U);
  for (const auto& d : s["designs"]) {
    SCOPED_TRACE(d["design"].get<std::string>());
    EXPECT_EQ(d["seeds"], 4);
    EXPECT_LE(d["fit"]["p10"].get<double>(), d["fit"]["median"].get<double>());
    EXPECT_LE(d["fit"]["median"].get<double>(), d["fit"]["p90"].get<double>());
    ASSERT_EQ(d["singular_values"].size(), 2U);
    const auto& c = d["criterion"];
    EXPECT_EQ(c["of"], 4);
    EXPECT_LE(c["wilson95"][0].get<double>(), c["share"].get<double>());
    EXPECT_GE(c["wilson95"][1].get<double>(), c["share"].get<double>());
    ASSERT_EQ(d["lengths"].size(), 4U);  // 25, 50, 75, 100 %
    EXPECT_EQ(d["lengths"][3]["met"], c["met"]);
    // T90 as stated: from it on, every share ≥ 0.9; the point before it (if any) below.
    if (d["t90"].is_null()) {
      EXPECT_LT(d["lengths"][3]["share"].get<double>(), 0.9);
    } else {
      bool on = false;
      double before = 0.0;
      for (const auto& p : d["lengths"]) {
        if (p["percent"] == d["t90"]["percent"]) on = true;
        if (on) {
          EXPECT_GE(p["share"].get<double>(), 0.9) << p.dump();
        } else {
          before = p["share"].get<double>();
        }
      }
      if (d["t90"]["percent"] != 25) {
        EXPECT_LT(before, 0.9);
      }
    }
  }
  EXPECT_NE(r.out.find("prbsSimDir"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("criterion met [95 %]"), std::string::npos) << r.out;
  // Progress on stderr, which is not a terminal here: plain lines with done/total and time.
  // The elapsed time is m:ss, whatever the machine's speed (sanitizer builds take longer).
  const auto last = r.out.find("montecarlo: 12/12 units, ");
  ASSERT_NE(last, std::string::npos) << r.out;
  const std::string clock = r.out.substr(last + 25, r.out.find(' ', last + 25) - (last + 25));
  const auto colon = clock.find(':');
  ASSERT_NE(colon, std::string::npos) << clock;
  EXPECT_GT(colon, 0U) << clock;
  EXPECT_EQ(clock.size() - colon, 3U) << clock;
  EXPECT_EQ(clock.find_first_not_of("0123456789:"), std::string::npos) << clock;
  EXPECT_EQ(r.out.substr(last + 25 + clock.size(), 9), " elapsed,") << r.out;
  EXPECT_NE(r.out.find(" left"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find('\r'), std::string::npos) << "a live bar was drawn on a pipe";
}

// On a terminal (a pseudo-terminal from util-linux `script`), one line redrawn in place.
TEST_F(MonteCarlo, OnATerminalProgressIsOneBarRedrawnInPlace) {
  const auto r = excite_cli_test::shell(
      "script -qec \"" + std::string(EXCITE_CLI) +
      " montecarlo --plant woodberry2x2 --designs prbsUnc --seeds 2 --length-step 50 -o " +
      path("mc") + " >/dev/null\" /dev/null");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("\r[" + std::string(24, ' ') + "] montecarlo: 0/2 units"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("\r[" + std::string(24, '#') + "] montecarlo: 2/2 units"), std::string::npos)
      << r.out;
  EXPECT_EQ(r.out.find("montecarlo: 0/2 units, 0:00 elapsed, time left unknown\n"),
            std::string::npos)
      << "plain lines on a terminal";
}

TEST_F(MonteCarlo, SigintStopsCleanlyKeepsFinishedUnitsAndTheRerunResumesToTheSameSummary) {
  const std::string run =
      "montecarlo --plant woodberry2x2 --designs stepSeq,prbsSeq,prbsUnc,"
      "prbsSimDir --seeds 6 --length-step 10 --threads 1";
  // GIVEN a run started as a process (its own argument vector, no shell between)
  std::vector<std::string> args = {EXCITE_CLI};
  {
    std::istringstream words(run + " -o " + path("mc"));
    for (std::string w; words >> w;) args.push_back(w);
  }
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_addopen(&files, 1, path("out.txt").c_str(), O_WRONLY | O_CREAT, 0644);
  posix_spawn_file_actions_addopen(&files, 2, path("err.txt").c_str(), O_WRONLY | O_CREAT, 0644);
  pid_t pid = 0;
  ASSERT_EQ(posix_spawn(&pid, argv[0], &files, nullptr, argv.data(), environ), 0);
  posix_spawn_file_actions_destroy(&files);
  // WHEN it has finished a unit, it gets SIGINT
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (units_in(path("mc")) == 0 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  ASSERT_GT(units_in(path("mc")), 0U) << bytes_of(path("err.txt"));
  ASSERT_EQ(::kill(pid, SIGINT), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  // THEN it exits 130, says how far it got, and keeps what finished (and only whole files)
  const std::string err = bytes_of(path("err.txt"));
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status) << "\n" << err;
  EXPECT_EQ(WEXITSTATUS(status), 130) << err;
  const std::size_t kept = units_in(path("mc"));
  EXPECT_GT(kept, 0U);
  EXPECT_LT(kept, 24U) << "the run was not stopped early";
  EXPECT_NE(err.find("interrupted: " + std::to_string(kept) + " of 24 units kept in"),
            std::string::npos)
      << err;
  EXPECT_FALSE(fs::exists(path("mc") + "/summary.json"));
  for (const auto& e : fs::recursive_directory_iterator(path("mc")))
    EXPECT_NE(e.path().filename().string().front(), '.') << "temporary file left: " << e.path();

  // AND the same command again resumes: only the rest runs, and the summary equals an
  // uninterrupted run's byte for byte
  const auto resumed = excite(run + " -o " + path("mc"));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.out;
  EXPECT_NE(resumed.out.find("(" + std::to_string(kept) + " from before)"), std::string::npos)
      << resumed.out;
  const auto whole = excite(run + " -o " + path("whole"));
  ASSERT_EQ(whole.exit_code, 0) << whole.out;
  EXPECT_EQ(bytes_of(path("mc") + "/summary.json"), bytes_of(path("whole") + "/summary.json"));
}

TEST_F(MonteCarlo, OneShardSevenShardsAndThreeThreadsGiveTheSameSummaryBytes) {
  ASSERT_EQ(excite(kRun + " --threads 1 -o " + path("one")).exit_code, 0);
  ASSERT_EQ(excite(kRun + " --threads 3 -o " + path("three")).exit_code, 0);
  std::string shards3, shards7;
  for (int i = 1; i <= 3; ++i) {
    const std::string dir = path(("s3-" + std::to_string(i)).c_str());
    const auto r = excite(kRun + " --shard " + std::to_string(i) + "/3 --threads " +
                          std::to_string(i == 2 ? 2 : 1) + " -o " + dir);
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_NE(r.out.find("shard " + std::to_string(i) + "/3 complete: 4 units"), std::string::npos)
        << r.out;
    EXPECT_FALSE(fs::exists(dir + "/summary.json"));
    shards3 = dir + " " + shards3;  // given in reverse order: merge does not care
  }
  for (int i = 1; i <= 7; ++i) {
    const std::string dir = path(("s7-" + std::to_string(i)).c_str());
    ASSERT_EQ(excite(kRun + " --shard " + std::to_string(i) + "/7 -o " + dir).exit_code, 0);
    shards7 += " " + dir;
  }
  const auto m3 = excite("montecarlo merge " + shards3 + " -o " + path("m3"));
  ASSERT_EQ(m3.exit_code, 0) << m3.out;
  EXPECT_NE(m3.out.find("prbsUnc"), std::string::npos) << m3.out;
  ASSERT_EQ(excite("montecarlo merge" + shards7 + " -o " + path("m7")).exit_code, 0);
  const std::string one = bytes_of(path("one") + "/summary.json");
  ASSERT_FALSE(one.empty());
  EXPECT_EQ(bytes_of(path("three") + "/summary.json"), one);
  EXPECT_EQ(bytes_of(path("m3") + "/summary.json"), one);
  EXPECT_EQ(bytes_of(path("m7") + "/summary.json"), one);

  // A missing shard, a duplicated one, and a shard with a unit missing are named.
  const std::string s1 = path("s3-1"), s2 = path("s3-2"), s3 = path("s3-3");
  auto r = excite("montecarlo merge " + s1 + " " + s3 + " -o " + path("bad"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("shard 2/3 missing, expected all 3 shards of the run"), std::string::npos)
      << r.out;
  fs::copy(s1, path("copy"), fs::copy_options::recursive);
  r = excite("montecarlo merge " + s1 + " " + s2 + " " + path("copy") + " " + s3 + " -o " +
             path("bad"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("shard 1/3 given twice: " + s1 + " and " + path("copy")), std::string::npos)
      << r.out;
  r = excite("montecarlo merge " + s1 + " " + path("s7-2") + " -o " + path("bad"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("shard = 2/7, expected one of 3"), std::string::npos) << r.out;
  ASSERT_TRUE(fs::remove(s2 + "/units/prbsUnc/seed-3.json"));  // k = 4: shard 2 of 3
  r = excite("montecarlo merge " + s1 + " " + s2 + " " + s3 + " -o " + path("bad"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find(s2 + ": unit prbsUnc seed 3 missing"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(path("bad") + "/summary.json"));
}

TEST_F(MonteCarlo, RefusesOptionsAndFoldersNamingTheFieldValueAndExpectation) {
  ASSERT_EQ(excite(kRun + " --shard 1/2 -o " + path("mc")).exit_code, 0);
  auto r = excite(run_of(5) + " --shard 1/2 -o " + path("mc"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("run.json: seeds = 4, expected 5 (this command's)"), std::string::npos)
      << r.out;
  r = excite(kRun + " -o " + path("mc"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("run.json: shard = 1/2, expected 1/1"), std::string::npos) << r.out;
  fs::create_directories(path("other"));
  std::ofstream(path("other") + "/notes.txt") << "mine\n";
  r = excite(kRun + " -o " + path("other"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("a folder with files and no run.json"), std::string::npos) << r.out;
  r = excite(kRun + " --shard 4/3 -o " + path("x"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("--shard = 4/3, expected i/N with 1 <= i <= N"), std::string::npos) << r.out;
  r = excite("montecarlo --plant woodberry2x2 --designs prbsSimDirr --seeds 2 -o " + path("x"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("--designs: prbsSimDirr, expected one of stepSeq"), std::string::npos)
      << r.out;
  r = excite("montecarlo --plant woodberry2x2 -o " + path("x"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.out.find("--seeds is required"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(path("x")));
}

// The --emit-slurm script run by a stand-in for sbatch (not Slurm: it runs each job of the
// array, then the merge job, here, in order, with SLURM_ARRAY_TASK_ID set as Slurm sets it).
// It checks the script's shell and the commands in it; the scheduler itself is not tested.
TEST_F(MonteCarlo, EmitSlurmScriptRunsItsArrayAndMergeToTheSingleProcessSummary) {
  const std::string out = path("cluster out");  // a space: refused, Slurm's --output is unquoted
  auto r = excite(kRun + " --emit-slurm " + path("submit.sh") + " -o '" + out + "'");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("expected a path without spaces or '%'"), std::string::npos) << r.out;

  r = excite(kRun + " --threads 1 --slurm-tasks 3 --emit-slurm " + path("submit.sh") + " -o " +
             path("cluster"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_FALSE(std::filesystem::exists(path("cluster"))) << "--emit-slurm ran the work";
  const std::string script = bytes_of(path("submit.sh"));
  EXPECT_NE(script.find("#SBATCH --array=1-3\n"), std::string::npos) << script;
  EXPECT_NE(script.find("--dependency=afterok:"), std::string::npos) << script;
  std::filesystem::create_directories(path("bin"));
  {
    std::ofstream stub(path("bin") + "/sbatch");
    stub << "#!/bin/sh\n"
            "job=$(mktemp); cat > \"$job\"\n"
            "range=$(sed -n 's/^#SBATCH --array=\\([0-9]*\\)-\\([0-9]*\\)$/\\1 \\2/p' \"$job\")\n"
            "if [ -n \"$range\" ]; then set -- $range; i=$1\n"
            "  while [ \"$i\" -le \"$2\" ]; do SLURM_ARRAY_TASK_ID=$i sh \"$job\" >> \"$STUB_LOG\" "
            "2>&1 || exit 1; i=$((i+1)); done\n"
            "else sh \"$job\" >> \"$STUB_LOG\" 2>&1 || exit 1; fi\n"
            "echo \"$$;cluster\"\n";
  }
  std::filesystem::permissions(path("bin") + "/sbatch", std::filesystem::perms::owner_all);
  r = excite_cli_test::shell("STUB_LOG=" + path("stub.log") + " PATH=" + path("bin") +
                             ":$PATH sh " + path("submit.sh"));
  ASSERT_EQ(r.exit_code, 0) << r.out << bytes_of(path("stub.log"));
  EXPECT_NE(r.out.find("(3 shards) and merge job"), std::string::npos) << r.out;
  ASSERT_EQ(excite(kRun + " --threads 1 -o " + path("one")).exit_code, 0);
  EXPECT_EQ(bytes_of(path("cluster") + "/summary.json"), bytes_of(path("one") + "/summary.json"))
      << bytes_of(path("stub.log"));
  EXPECT_TRUE(std::filesystem::exists(path("cluster") + "/shard-3/run.json"));
}

// Issue 41 §4: the run with the controller on, in process: woodberry2x2 under the example PI,
// prbsUnc as an MV dither, identified two-stage; its options kept in run.json, the summary
// and the Slurm script, and refused without --controller.
TEST_F(MonteCarlo, RunsClosedLoopUnderAControllerFileAndSaysSo) {
  const std::string pi = std::string(EXCITE_CONTROL_EXAMPLES) + "/woodberry2x2.pi.toml";
  const std::string run =
      "montecarlo --plant woodberry2x2 --designs prbsUnc --seeds 2 "
      "--length-step 50 --controller " +
      pi + " --excitation mv";
  auto r = excite(run + " --threads 2 -o " + path("cl"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("controller on: closed loop in process under " + pi), std::string::npos)
      << r.out;
  const nlohmann::json s = nlohmann::json::parse(bytes_of(path("cl") + "/summary.json"));
  EXPECT_EQ(s["run"]["closed_loop"]["excitation"], "mv");
  EXPECT_EQ(s["designs"][0]["criterion"]["of"], 2);
  EXPECT_TRUE(s["designs"][0]["crossfit_worst"]["median"].is_null()) << s["designs"][0].dump();
  const nlohmann::json config = nlohmann::json::parse(bytes_of(path("cl") + "/run.json"));
  EXPECT_EQ(config["closed_loop"]["controller"], pi);

  r = excite(run + " --emit-slurm " + path("job.sh") + " -o " + path("slurm"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const std::string script = bytes_of(path("job.sh"));
  EXPECT_NE(script.find(" --controller '" + pi +
                        "' --excitation mv --method two-stage --limit-fraction 0.5 "
                        "--mv-fraction 0 --directions none --switching loop --prbs-phase 0 "
                        "--controller-perturb 0 "
                        "--disturbance-std 0 --disturbance-tau-min 0 "),
            std::string::npos)
      << script;

  // Setpoint excitation under colaA's DMC: the designs at the loop's pace by default, where
  // the DMC follows r along the weakest output direction far slower than the plant's τ_L
  // (host/campaign/closed_loop_designs.hpp at_the_loops_pace): a longer switching time, so
  // fewer samples in the same PRBS order; --switching plant keeps the open-loop design.
  const std::string dmc = std::string(EXCITE_CONTROL_EXAMPLES) + "/colaA.dmc.toml";
  const std::string cola =
      "montecarlo --plant colaA --designs prbsUnc --seeds 1 --length-step 50 "
      "--mv-fraction 1 --controller " +
      dmc;
  r = excite(cola + " -o " + path("loop"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("setpoint excitation at the loop's pace"), std::string::npos) << r.out;
  r = excite(cola + " --switching plant -o " + path("plant"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_EQ(r.out.find("at the loop's pace"), std::string::npos) << r.out;
  const nlohmann::json loop = nlohmann::json::parse(bytes_of(path("loop") + "/summary.json"));
  const nlohmann::json plant = nlohmann::json::parse(bytes_of(path("plant") + "/summary.json"));
  EXPECT_EQ(loop["run"]["closed_loop"]["switching"], "loop");
  EXPECT_EQ(plant["run"]["closed_loop"]["switching"], "plant");
  EXPECT_EQ(plant["designs"][0]["samples"], 511 * 21);  // T_sw 21 min from τ_L = 15 min
  EXPECT_NE(loop["designs"][0]["samples"], plant["designs"][0]["samples"]);

  r = excite("montecarlo --plant woodberry2x2 --seeds 1 --excitation mv -o " + path("x"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.out.find("--excitation requires --controller"), std::string::npos) << r.out;
  r = excite(run + " --directions output -o " + path("x"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("--directions = output with --excitation = mv, expected setpoint"),
            std::string::npos)
      << r.out;
  r = excite("montecarlo --plant woodberry2x2 --seeds 1 --designs prbsSimDir --controller " + pi +
             " -o " + path("x"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("--designs = prbsSimDir, expected a plain preset"), std::string::npos)
      << r.out;
  EXPECT_FALSE(fs::exists(path("x")));
}
