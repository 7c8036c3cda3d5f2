// SPDX-License-Identifier: MIT
// The library plants as TOML text in the element grammar: the single source of truth.
// Transcribed from the thesis equations named in each description (SPEC §7).
#include <array>
#include <stdexcept>
#include <string>

#include "sim/library/library.hpp"

namespace excite::sim {
namespace {

struct LibraryEntry {
  std::string_view name;
  std::string_view toml;
};

constexpr std::array<LibraryEntry, 6> kPlants{{
    {"alatiqi4x4", R"toml(
name = "alatiqi4x4"
description = "4x4 distillation column with side stripper, Alatiqi and Luyben (1986); thesis 6.3.1 = B.0.5"
time_unit = "min"
G = [
  ["4.09 e^-1.3s / ((33s+1)(8.3s+1))", "6.36 e^-1.2s / ((31.6s+1)(20s+1))", "-0.25 e^-1.4s / (21s+1)", "-0.49 e^-6s / (22s+1)"],
  ["-4.17 e^-5s / (45s+1)", "6.93 e^-1.02s / (44.6s+1)", "-0.05 e^-6s / (34.5s+1)^2", "1.53 e^-3.8s / (48s+1)"],
  ["1.73 e^-18s / (13s+1)^2", "5.11 e^-12s / (13.3s+1)^2", "4.61 e^-1.01s / (18.5s+1)", "-5.49 e^-1.5s / (15s+1)"],
  ["-11.2 e^-2.6s / ((43s+1)(6.5s+1))", "14(10s+1) e^-0.02s / ((45s+1)(17.4s^2+3s+1))", "-0.1 e^-0.05s / ((31.6s+1)(5s+1))", "4.49 e^-0.6s / ((48s+1)(6.3s+1))"],
]
)toml"},
    {"column2x2", R"toml(
name = "column2x2"
description = "2x2 distillation column (LV configuration), Skogestad et al. (1988); thesis 5.3.1 = B.0.2"
time_unit = "min"
inputs = ["L", "V"]
outputs = ["yD", "xB"]
G = [
  ["87.8/(194s+1)",  "-87.8/(194s+1) + 1.4/(15s+1)"],
  ["108.2/(194s+1)", "-108.2/(194s+1) - 1.4/(15s+1)"],
]
)toml"},
    {"heatex2x2", R"toml(
name = "heatex2x2"
description = "2x2 heat exchanger, Jacobsen and Skogestad (1994); thesis 5.3.3 = B.0.1"
time_unit = "min"
G = [
  ["-89.243*21(4.76s+1) / ((100s+1)(2.439s+1))", "89.243*20 / ((100s+1)(2.439s+1))"],
  ["-89.243*20 / ((100s+1)(2.439s+1))",          "89.243*21(4.76s+1) / ((100s+1)(2.439s+1))"],
]
)toml"},
    {"woodberry2x2", R"toml(
name = "woodberry2x2"
description = "Wood-Berry 2x2 distillation column, Wood and Berry (1973); thesis B.0.3"
time_unit = "min"
G = [
  ["12.8 e^-1s / (16.7s+1)", "-18.9 e^-3s / (21s+1)"],
  ["6.6 e^-7s / (10.9s+1)",  "-19.4 e^-3s / (14.4s+1)"],
]
)toml"},
    {"column3x3", R"toml(
name = "column3x3"
description = "3x3 distillation column, Koung and MacGregor (1994), Li and Lee (1996); thesis B.0.4"
time_unit = "min"
G = [
  ["6 e^-5s / (22s+1)", "20 e^-5s / (337s+1)",  "-1 e^-5s / (10s+1)"],
  ["8 e^-5s / (50s+1)", "77 e^-3s / (28s+1)",   "-5 e^-5s / (10s+1)"],
  ["9 e^-5s / (50s+1)", "-37 e^-5s / (166s+1)", "-103 e^-4s / (23s+1)"],
]
)toml"},
    {"twoweak4x4", R"toml(
name = "twoweak4x4"
description = "4x4 example with two small singular values; thesis 6.4.1 = B.0.6"
time_unit = "min"
G = [
  ["0.173 e^-3.79s / (21.74s+1)^2", "-3.4 e^-7.75s / (22.22s+1)^2", "-8.66 e^-1.59s / (11.36s+1)", "11.94 e^-27.33s / (33.3s+1)"],
  ["-0.268 e^-60s / (400s+1)", "2.79 e^-0.71s / (66.67s+1)^2", "5.05 e^-2.24s / (14.29s+1)", "-5.65 e^-8.72s / (250s+1)^2"],
  ["-0.084 e^-0.68s / (2.38s+1)^2", "0.94 e^-0.59s / (7.14s+1)^2", "1.31 e^-0.42s / (1.43s+1)^2", "-0.56 e^-1s"],
  ["-0.047 e^-0.52s / (11.11s+1)", "-15.5 e^-0.48s / (6.90s+1)^2", "-9.03 e^-1.91s / (12.19s+1)", "-8.71 e^-1s"],
]
)toml"},
}};

const LibraryEntry& find(std::string_view name) {
  for (const LibraryEntry& e : kPlants) {
    if (e.name == name) return e;
  }
  std::string known;
  for (const LibraryEntry& e : kPlants) known += (known.empty() ? "" : ", ") + std::string(e.name);
  throw std::invalid_argument("plant name \"" + std::string(name) +
                              "\": unknown, expected one of " + known);
}

}  // namespace

std::vector<std::string> library_plant_names() {
  std::vector<std::string> names;
  for (const LibraryEntry& e : kPlants) names.emplace_back(e.name);
  return names;
}

std::string_view library_plant_toml(std::string_view name) {
  return find(name).toml;
}

PlantDefinition library_plant_definition(std::string_view name) {
  const LibraryEntry& e = find(name);
  return plant_from_toml(e.toml, "library plant " + std::string(e.name));
}

TransferMatrix library_plant(std::string_view name) {
  return library_plant_definition(name).g;
}

}  // namespace excite::sim
