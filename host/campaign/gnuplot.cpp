// SPDX-License-Identifier: MIT
#include "host/campaign/gnuplot.hpp"

#include <algorithm>
#include <chrono>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "host/campaign/parallel.hpp"
#include "host/process/child_process.hpp"

namespace excite::host {
namespace {

namespace fs = std::filesystem;

// The SVG files a script draws: the names in its `set output '…'` lines.
std::vector<std::string> outputs_of(const fs::path& script) {
  std::ifstream in(script);
  std::vector<std::string> names;
  const std::string key = "set output '";
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(key, 0) != 0) continue;
    std::string name;
    for (std::size_t i = key.size(); i < line.size(); ++i) {
      if (line[i] != '\'') {
        name += line[i];
      } else if (i + 1 < line.size() && line[i + 1] == '\'') {
        name += '\'';
        ++i;
      } else {
        break;
      }
    }
    names.push_back(name);
  }
  return names;
}

bool ends_whole(const fs::path& svg) {
  std::ifstream in(svg, std::ios::binary);
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  const std::size_t end = text.find_last_not_of(" \n");
  return end != std::string::npos && end >= 5 && text.compare(end - 5, 6, "</svg>") == 0;
}

void run_gnuplot(const fs::path& folder, const std::string& script) {
  // "./NAME": a name starting with '-' is still a file to gnuplot, not an option.
  ChildProcess gnuplot("gnuplot", {"./" + script}, {}, folder);
  const std::string output = gnuplot.read_all(std::chrono::minutes(10));
  const std::optional<int> code = gnuplot.wait(std::chrono::seconds(5));
  if (!code || *code != 0) {
    throw std::runtime_error("gnuplot " + (folder / script).string() + " failed (" +
                             (!code         ? std::string("still running after 10 min")
                              : *code > 128 ? "ended by signal " + std::to_string(*code - 128)
                                            : "exit code " + std::to_string(*code)) +
                             "): " + output);
  }
  for (const std::string& svg : outputs_of(folder / script)) {
    if (!ends_whole(folder / svg)) {
      throw std::runtime_error("gnuplot " + (folder / script).string() + ": " +
                               (folder / svg).string() +
                               " is missing or cut short (no closing </svg>): " + output);
    }
  }
}

}  // namespace

std::string gnuplot_string(const std::string& text) {
  std::string out = "'";
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte == 0x7f) {
      throw std::invalid_argument("'" + text +
                                  "': a control character in a gnuplot string; expected "
                                  "printable text");
    }
    out += c == '\'' ? std::string("''") : std::string(1, c);
  }
  return out + "'";
}

void run_gnuplot_scripts(const fs::path& folder, const std::vector<std::string>& scripts,
                         int threads) {
  parallel_for(static_cast<int>(scripts.size()), std::max(1, threads),
               [&](int k) { run_gnuplot(folder, scripts[static_cast<std::size_t>(k)]); });
}

}  // namespace excite::host
