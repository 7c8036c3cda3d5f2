// SPDX-License-Identifier: MIT
#include "host/campaign/gnuplot.hpp"

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "host/campaign/parallel.hpp"

namespace excite::host {
namespace {

void run_gnuplot(const std::filesystem::path& script) {
  const std::string command = "gnuplot '" + script.string() + "' 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) throw std::runtime_error("gnuplot: cannot be started");
  std::string output;
  char buffer[512];
  while (std::fgets(buffer, sizeof buffer, pipe) != nullptr) output += buffer;
  if (pclose(pipe) != 0)
    throw std::runtime_error("gnuplot " + script.string() + " failed: " + output);
}

}  // namespace

std::string gnuplot_string(const std::string& text) {
  std::string out = "'";
  for (const char c : text) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out + "'";
}

void run_gnuplot_scripts(const std::filesystem::path& folder, int threads) {
  std::vector<std::filesystem::path> scripts;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    if (entry.path().extension() == ".gp") scripts.push_back(entry.path());
  }
  std::sort(scripts.begin(), scripts.end());
  parallel_for(static_cast<int>(scripts.size()), std::max(1, threads),
               [&](int k) { run_gnuplot(scripts[static_cast<std::size_t>(k)]); });
}

}  // namespace excite::host
