// SPDX-License-Identifier: MIT
#include "sim/server/server_config.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "sim/server/server_layout.hpp"

namespace excite::sim::server {
namespace {

// Reads one TOML table with a fixed set of keys; every failure names the dotted field.
class Reader {
 public:
  Reader(const toml::table& table, std::string prefix, std::string_view source)
      : table_(table), prefix_(std::move(prefix)), source_(source) {}

  [[noreturn]] void fail(const std::string& key, const std::string& value,
                         const std::string& expected) const {
    throw std::invalid_argument(std::string(source_) + ": " + field(key) + " = " + value +
                                ": expected " + expected);
  }

  std::string field(const std::string& key) const {
    return prefix_.empty() ? key : prefix_ + "." + key;
  }

  void only_keys(std::initializer_list<std::string_view> known) const {
    for (const auto& [key, node] : table_) {
      if (std::find(known.begin(), known.end(), key.str()) == known.end()) {
        std::string list;
        for (std::string_view k : known) list += (list.empty() ? "" : ", ") + std::string(k);
        fail(std::string(key.str()), "(unknown key)", "one of " + list);
      }
    }
  }

  const toml::node* get(const std::string& key) const { return table_.get(key); }
  std::string_view source() const { return source_; }

  std::optional<std::string> text(const std::string& key) const {
    const toml::node* node = get(key);
    if (node == nullptr) return std::nullopt;
    const auto s = node->value<std::string>();
    if (!s || !node->is_string()) fail(key, describe(*node), "a string");
    return *s;
  }

  std::optional<double> number(const std::string& key) const {
    const toml::node* node = get(key);
    if (node == nullptr) return std::nullopt;
    if (!node->is_number()) fail(key, describe(*node), "a number");
    const double x = *node->value<double>();
    if (!std::isfinite(x)) fail(key, describe(*node), "a finite number");
    return x;
  }

  std::optional<std::int64_t> integer(const std::string& key, std::int64_t lo, std::int64_t hi,
                                      const std::string& what) const {
    const toml::node* node = get(key);
    if (node == nullptr) return std::nullopt;
    if (!node->is_integer()) fail(key, describe(*node), "an integer: " + what);
    const std::int64_t v = *node->value<std::int64_t>();
    if (v < lo || v > hi) fail(key, std::to_string(v), what);
    return v;
  }

  // A number or an array of numbers.
  std::vector<double> numbers(const std::string& key, bool scalar_allowed) const {
    std::vector<double> out;
    const toml::node* node = get(key);
    if (node == nullptr) return out;
    if (scalar_allowed && node->is_number()) return {*number(key)};
    const toml::array* array = node->as_array();
    if (array == nullptr) {
      fail(key, describe(*node),
           scalar_allowed ? "a number or an array of numbers" : "an array of numbers");
    }
    for (std::size_t i = 0; i < array->size(); ++i) {
      const toml::node& item = (*array)[i];
      const std::string item_key = key + "[" + std::to_string(i) + "]";
      if (!item.is_number()) fail(item_key, describe(item), "a number");
      const double x = *item.value<double>();
      if (!std::isfinite(x)) fail(item_key, describe(item), "a finite number");
      out.push_back(x);
    }
    return out;
  }

  static std::string describe(const toml::node& node) {
    std::ostringstream os;
    if (node.is_string()) {
      os << '"' << *node.value<std::string>() << '"';
    } else if (node.is_table()) {
      os << "(a table)";
    } else if (node.is_array()) {
      os << "(an array)";
    } else {
      node.visit([&os](const auto& n) { os << n; });
    }
    return os.str();
  }

 private:
  const toml::table& table_;
  std::string prefix_;
  std::string_view source_;
};

const toml::table& sub_table(const Reader& parent, const toml::node* node, const std::string& key) {
  const toml::table* table = node->as_table();
  if (table == nullptr) parent.fail(key, Reader::describe(*node), "a table");
  return *table;
}

PlantSettings read_plant(const Reader& r) {
  r.only_keys({"library", "file", "sample_time_min", "input_baseline", "output_baseline",
               "noise_variance", "noise_seed", "watchdog_s", "input_min", "input_max"});
  PlantSettings plant;
  plant.library = r.text("library").value_or("");
  plant.file = r.text("file").value_or("");
  if (!plant.library.empty() && !plant.file.empty()) {
    r.fail("file", "\"" + plant.file + "\"", "either library or file, not both");
  }
  if (const auto t = r.number("sample_time_min")) {
    if (!(*t > 0.0)) r.fail("sample_time_min", std::to_string(*t), "a sample time > 0 minutes");
    plant.sample_time_min = *t;
  }
  plant.input_baseline = r.numbers("input_baseline", false);
  plant.output_baseline = r.numbers("output_baseline", false);
  plant.noise_variance = r.numbers("noise_variance", true);
  for (std::size_t i = 0; i < plant.noise_variance.size(); ++i) {
    if (plant.noise_variance[i] < 0.0) {
      r.fail("noise_variance", std::to_string(plant.noise_variance[i]), "variances >= 0");
    }
  }
  if (const auto seed =
          r.integer("noise_seed", 0, std::numeric_limits<std::int64_t>::max(), "a seed >= 0")) {
    plant.noise_seed = static_cast<std::uint64_t>(*seed);
  }
  if (const auto w = r.number("watchdog_s")) {
    if (*w < 0.0) r.fail("watchdog_s", std::to_string(*w), "wall-clock seconds >= 0 (0: off)");
    plant.watchdog_s = *w;
  }
  plant.input_min = r.numbers("input_min", false);
  plant.input_max = r.numbers("input_max", false);
  if (plant.input_min.size() != plant.input_max.size()) {
    r.fail("input_max", "(" + std::to_string(plant.input_max.size()) + " values)",
           "as many values as input_min (" + std::to_string(plant.input_min.size()) + ")");
  }
  for (std::size_t i = 0; i < plant.input_min.size(); ++i) {
    if (!(plant.input_min[i] < plant.input_max[i])) {
      r.fail("input_max[" + std::to_string(i) + "]", std::to_string(plant.input_max[i]),
             "a limit above input_min[" + std::to_string(i) +
                 "] = " + std::to_string(plant.input_min[i]));
    }
  }
  return plant;
}

hal::modbus::RegisterEntry read_entry(const Reader& r, bool setpoint) {
  r.only_keys({"name", "address", "function_code", "type", "word_order", "eng_min", "eng_max",
               "raw_min", "raw_max"});
  hal::modbus::RegisterEntry e;
  e.name = r.text("name").value_or("");
  const auto address = r.integer("address", 0, 65535, "a register address 0..65535");
  if (!address) r.fail("address", "(missing)", "a register address 0..65535");
  e.address = static_cast<std::uint32_t>(*address);
  const auto fc = r.integer("function_code", 0, 255, "a Modbus function code");
  if (!fc && !setpoint) r.fail("function_code", "(missing)", "3 (holding) or 4 (input)");
  e.function_code = static_cast<int>(fc.value_or(16));
  e.type = r.text("type").value_or("float32");
  e.word_order = r.text("word_order").value_or("ABCD");
  e.eng_min = r.number("eng_min").value_or(0.0);
  e.eng_max = r.number("eng_max").value_or(0.0);
  if (const auto v = r.integer("raw_min", -32768, 65535, "-32768..65535")) {
    e.raw_min = static_cast<std::int32_t>(*v);
  }
  if (const auto v = r.integer("raw_max", -32768, 65535, "-32768..65535")) {
    e.raw_max = static_cast<std::int32_t>(*v);
  }
  return e;
}

std::vector<hal::modbus::RegisterEntry> read_entries(const Reader& r, const std::string& key,
                                                     bool setpoint) {
  std::vector<hal::modbus::RegisterEntry> out;
  const toml::node* node = r.get(key);
  if (node == nullptr) return out;
  const toml::array* array = node->as_array();
  if (array == nullptr) r.fail(key, Reader::describe(*node), "an array of tables ([[...]])");
  for (std::size_t i = 0; i < array->size(); ++i) {
    const std::string item_key = key + "[" + std::to_string(i) + "]";
    const toml::table* t = (*array)[i].as_table();
    if (t == nullptr) r.fail(item_key, Reader::describe((*array)[i]), "a table");
    out.push_back(read_entry(Reader(*t, r.field(item_key), r.source()), setpoint));
  }
  return out;
}

ServerRegisters read_registers(const Reader& r) {
  r.only_keys({"setpoints", "values", "heartbeat_address", "heartbeat_echo_address",
               "heartbeat_echo_function_code", "control_address", "command_address", "write_chunk",
               "read_chunk"});
  ServerRegisters regs;
  regs.map.setpoints = read_entries(r, "setpoints", true);
  regs.map.values = read_entries(r, "values", false);
  const auto hb = r.integer("heartbeat_address", 0, 65535, "a register address 0..65535");
  if (!hb) r.fail("heartbeat_address", "(missing)", "a holding register address 0..65535");
  regs.map.heartbeat_address = static_cast<std::uint32_t>(*hb);
  const auto echo = r.integer("heartbeat_echo_address", 0, 65535, "a register address 0..65535");
  if (!echo) r.fail("heartbeat_echo_address", "(missing)", "a register address 0..65535");
  regs.heartbeat_echo_address = static_cast<std::uint32_t>(*echo);
  regs.heartbeat_echo_function_code = static_cast<int>(
      r.integer("heartbeat_echo_function_code", 3, 4, "3 (holding) or 4 (input register)")
          .value_or(3));
  if (const auto c = r.integer(
          "control_address", 0, 65536 - control_block_size,
          "a holding address with room for " + std::to_string(control_block_size) + " registers")) {
    regs.control_address = static_cast<std::uint32_t>(*c);
  }
  if (const auto c =
          r.integer("command_address", 0, 65535, "a holding register address 0..65535")) {
    regs.command_address = static_cast<std::uint32_t>(*c);
  }
  if (const auto w = r.integer("write_chunk", 2, 123, "2..123")) {
    regs.map.write_chunk = static_cast<std::uint32_t>(*w);
  }
  if (const auto w = r.integer("read_chunk", 2, 125, "2..125")) {
    regs.map.read_chunk = static_cast<std::uint32_t>(*w);
  }
  return regs;
}

}  // namespace

ServerConfig parse_server_config(std::string_view toml_text, std::string_view source) {
  toml::table root;
  try {
    root = toml::parse(toml_text, source);
  } catch (const toml::parse_error& e) {
    std::ostringstream os;
    os << source << ": TOML syntax error at line " << e.source().begin.line << ", column "
       << e.source().begin.column << ": " << e.description();
    throw std::invalid_argument(os.str());
  }
  const Reader top(root, "", source);
  top.only_keys({"plant", "registers"});
  ServerConfig config;
  if (const toml::node* p = top.get("plant")) {
    config.plant = read_plant(Reader(sub_table(top, p, "plant"), "plant", source));
  }
  const toml::node* r = top.get("registers");
  if (r == nullptr) top.fail("registers", "(missing)", "a [registers] table");
  config.registers = read_registers(Reader(sub_table(top, r, "registers"), "registers", source));
  check_registers(config.registers, source);
  return config;
}

ServerConfig load_server_config(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw std::invalid_argument(path.string() + ": cannot read the configuration file");
  }
  std::ostringstream text;
  text << in.rdbuf();
  ServerConfig config = parse_server_config(text.str(), path.string());
  config.base_directory = path.parent_path();
  return config;
}

}  // namespace excite::sim::server
