// SPDX-License-Identifier: MIT
#include "host/campaign/gnuplot.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "host/campaign/svg_compact.hpp"
#include "host/output/whole_file.hpp"
#include "host/process/child_process.hpp"
#include "host/process/parallel.hpp"

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

std::string read_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

bool ends_whole(const std::string& text) {
  const std::size_t end = text.find_last_not_of(" \n");
  return end != std::string::npos && end >= 5 && text.compare(end - 5, 6, "</svg>") == 0;
}

// One gnuplot process draws `scripts` in turn (`reset` between them, so no setting of one
// leaks into the next; the terminal and output are each script's own): starting gnuplot
// costs more than drawing most figures.
void run_gnuplot(const fs::path& folder, const std::string& batch,
                 const std::vector<std::string>& scripts) {
  std::string text;
  for (const std::string& script : scripts) text += "reset\nload " + gnuplot_string(script) + '\n';
  write_figure_source(folder, batch, text);
  // "./NAME": a name starting with '-' is still a file to gnuplot, not an option.
  ChildProcess gnuplot("gnuplot", {"./" + batch}, {}, folder);
  const std::string output = gnuplot.read_all(std::chrono::minutes(10));
  const std::optional<int> code = gnuplot.wait(std::chrono::seconds(5));
  if (!code || *code != 0) {
    throw std::runtime_error("gnuplot " + (folder / batch).string() + " failed (" +
                             (!code         ? std::string("still running after 10 min")
                              : *code > 128 ? "ended by signal " + std::to_string(*code - 128)
                                            : "exit code " + std::to_string(*code)) +
                             "): " + output);
  }
  for (const std::string& script : scripts) {
    for (const std::string& svg : outputs_of(folder / script)) {
      const std::string drawn = read_text(folder / svg);
      if (!ends_whole(drawn)) {
        throw std::runtime_error("gnuplot " + (folder / script).string() + ": " +
                                 (folder / svg).string() +
                                 " is missing or cut short (no closing </svg>): " + output);
      }
      write_whole_file(folder / svg, compact_gnuplot_svg(drawn));
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
                                  "': a control character in a gnuplot string, expected "
                                  "printable text");
    }
    out += c == '\'' ? std::string("''") : std::string(1, c);
  }
  return out + "'";
}

std::string source_name(const std::string& file) {
  return std::string(kFigureSources) + "/" + file;
}

void write_figure_source(const fs::path& figures, const std::string& name, std::string_view bytes) {
  const fs::path path = figures / name;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  const bool written =
      f != nullptr && std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  const int error = errno;
  const bool closed = f != nullptr && std::fclose(f) == 0;
  if (!written || !closed) {
    throw std::runtime_error(path.string() + ": cannot be written (" +
                             std::strerror(written ? errno : error) + ")");
  }
}

void make_figure_sources(const fs::path& figures) {
  fs::remove_all(figures / kFigureSources);
  fs::create_directories(figures / kFigureSources);
}

void remove_figure_sources(const fs::path& figures) {
  fs::remove_all(figures / kFigureSources);
}

void run_gnuplot_scripts(const fs::path& folder, const std::vector<std::string>& scripts,
                         int threads) {
  fs::create_directories(folder / kFigureSources);
  // One batch per thread, the scripts dealt round-robin.
  const auto batches = static_cast<std::size_t>(std::clamp<std::size_t>(
      static_cast<std::size_t>(std::max(1, threads)), 1, std::max<std::size_t>(1, scripts.size())));
  std::vector<std::vector<std::string>> batch(batches);
  for (std::size_t k = 0; k < scripts.size(); ++k) batch[k % batches].push_back(scripts[k]);
  parallel_for(static_cast<int>(batches), static_cast<int>(batches), [&](int k) {
    const std::string name = source_name("batch-" + std::to_string(k) + ".gp");
    run_gnuplot(folder, name, batch[static_cast<std::size_t>(k)]);
  });
}

}  // namespace excite::host
