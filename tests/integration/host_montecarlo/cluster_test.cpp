// SPDX-License-Identifier: MIT
// A real single-node Slurm cluster (label cluster): munged, slurmctld and slurmd of Debian's
// munge and slurm-wlm started here as child processes with a generated slurm.conf (their own
// munge key and socket, ports, state and spool folders in a scratch folder: nothing of the
// machine's configuration is used or changed), the script of `excite montecarlo --emit-slurm`
// submitted with the real sbatch, and the merged summary compared byte for byte with the
// single-process run's. Skipped (tests/skips/expected.txt) when those programs are missing
// or the test is not root (slurmd runs the jobs as root here).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "../host_cli/cli_process.hpp"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using excite_cli_test::bytes_of;
using excite_cli_test::excite;
using excite_cli_test::shell;

int free_port() {
  const int s = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t n = sizeof a;
  ::bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a);
  ::getsockname(s, reinterpret_cast<sockaddr*>(&a), &n);
  ::close(s);
  return ntohs(a.sin_port);
}

std::string short_hostname() {
  char name[256] = {};
  ::gethostname(name, sizeof name - 1);
  const std::string h(name);
  return h.substr(0, h.find('.'));
}

class SlurmCluster : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const char* program :
         {"/usr/sbin/munged", "/usr/sbin/mungekey", "/usr/sbin/slurmctld", "/usr/sbin/slurmd",
          "/usr/bin/sbatch", "/usr/bin/sinfo", "/usr/bin/squeue"}) {
      if (!fs::exists(program))
        GTEST_SKIP() << program << " missing (apt-get install slurm-wlm munge)";
    }
    if (::geteuid() != 0) GTEST_SKIP() << "not root: slurmd here runs the jobs as root";
    dir_ = fs::path("/tmp") / ("excite_slurm_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    for (const char* sub : {"state", "spool", "log"}) fs::create_directories(dir_ / sub);
    fs::permissions(dir_, fs::perms::owner_all);
    conf_ = (dir_ / "slurm.conf").string();
    const std::string d = dir_.string();
    ASSERT_EQ(shell("/usr/sbin/mungekey -c -k " + d + "/munge.key").exit_code, 0);
    fs::permissions(dir_ / "munge.key", fs::perms::owner_read | fs::perms::owner_write);
    const std::string host = short_hostname();
    std::ofstream(conf_) << "ClusterName=excite\nSlurmctldHost=" << host << "(127.0.0.1)\n"
                         << "SlurmctldPort=" << free_port() << "\nSlurmdPort=" << free_port()
                         << "\nSlurmUser=root\nSlurmdUser=root\nAuthType=auth/munge\n"
                            "CredType=cred/munge\nAuthInfo=socket="
                         << d << "/munge.sock\nStateSaveLocation=" << d
                         << "/state\nSlurmdSpoolDir=" << d << "/spool\nSlurmctldPidFile=" << d
                         << "/slurmctld.pid\nSlurmdPidFile=" << d
                         << "/slurmd.pid\nSlurmctldLogFile=" << d
                         << "/log/slurmctld.log\nSlurmdLogFile=" << d
                         << "/log/slurmd.log\nProctrackType=proctrack/linuxproc\n"
                            "TaskPlugin=task/none\nJobAcctGatherType=jobacct_gather/none\n"
                            "AccountingStorageType=accounting_storage/none\n"
                            "SchedulerType=sched/backfill\nSelectType=select/cons_tres\n"
                            "SelectTypeParameters=CR_Core\nReturnToService=2\nMpiDefault=none\n"
                         << "NodeName=" << host << " NodeAddr=127.0.0.1 CPUs=2 State=UNKNOWN\n"
                         << "PartitionName=debug Nodes=" << host
                         << " Default=YES MaxTime=INFINITE State=UP\n";
    ::setenv("SLURM_CONF", conf_.c_str(), 1);
    start({"/usr/sbin/munged", "-F", "--force", "--socket=" + d + "/munge.sock",
           "--key-file=" + d + "/munge.key", "--pid-file=" + d + "/munged.pid",
           "--log-file=" + d + "/log/munged.log", "--seed-file=" + d + "/munge.seed"},
          "munged");
    wait_for([&] { return fs::exists(dir_ / "munge.sock"); }, "munged's socket");
    start({"/usr/sbin/slurmctld", "-D"}, "slurmctld");
    start({"/usr/sbin/slurmd", "-D"}, "slurmd");
    wait_for([] { return shell("/usr/bin/sinfo -h -o %T").out.find("idle") != std::string::npos; },
             "the node idle in sinfo");
  }

  void TearDown() override {
    for (auto it = children_.rbegin(); it != children_.rend(); ++it) ::kill(*it, SIGTERM);
    for (const pid_t pid : children_) ::waitpid(pid, nullptr, 0);
    ::unsetenv("SLURM_CONF");
    if (!dir_.empty() && !HasFailure()) fs::remove_all(dir_);
  }

  void start(std::vector<std::string> args, const std::string& name) {
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t files;
    posix_spawn_file_actions_init(&files);
    const std::string out = (dir_ / "log" / (name + ".out")).string();
    posix_spawn_file_actions_addopen(&files, 1, out.c_str(), O_WRONLY | O_CREAT, 0644);
    posix_spawn_file_actions_adddup2(&files, 1, 2);
    pid_t pid = 0;
    ASSERT_EQ(::posix_spawn(&pid, argv[0], &files, nullptr, argv.data(), environ), 0) << name;
    posix_spawn_file_actions_destroy(&files);
    children_.push_back(pid);
  }

  template <class Ready>
  void wait_for(Ready ready, const char* what, int seconds = 60) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(seconds);
    while (!ready()) {
      ASSERT_LT(std::chrono::steady_clock::now(), end)
          << what << " not there after " << seconds << " s; logs in " << dir_;
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
  }

  fs::path dir_;
  std::string conf_;
  std::vector<pid_t> children_;
};

}  // namespace

TEST_F(SlurmCluster, EmittedJobArrayAndMergeGiveTheSingleProcessSummary) {
  const std::string run =
      "montecarlo --plant woodberry2x2 --designs stepSeq,prbsUnc,prbsSimDir --seeds 4 "
      "--first-seed 3 --length-step 25 --threads 1";
  const std::string out = (dir_ / "out").string();
  ASSERT_EQ(
      excite(run + " --slurm-tasks 3 --emit-slurm " + (dir_ / "submit.sh").string() + " -o " + out)
          .exit_code,
      0);
  const auto submitted = shell("sh " + (dir_ / "submit.sh").string());
  ASSERT_EQ(submitted.exit_code, 0) << submitted.out;
  EXPECT_NE(submitted.out.find("(3 shards) and merge job"), std::string::npos) << submitted.out;
  wait_for(
      [&] { return fs::exists(out + "/summary.json") && shell("/usr/bin/squeue -h").out.empty(); },
      "the merged summary", 300);
  for (int i = 1; i <= 3; ++i)
    EXPECT_TRUE(fs::exists(out + "/shard-" + std::to_string(i) + "/run.json")) << i;
  ASSERT_EQ(excite(run + " -o " + (dir_ / "one").string()).exit_code, 0);
  EXPECT_EQ(bytes_of(out + "/summary.json"), bytes_of((dir_ / "one/summary.json").string()))
      << bytes_of(out + "/logs/merge.out");
}
