// SPDX-License-Identifier: MIT
#include "host/design/table.hpp"

#include <stdexcept>
#include <vector>

#include "firmware/signal/generate.hpp"

namespace excite::host {

Table make_table(const signal::Recipe& recipe) {
  Table table(recipe.samples, recipe.channels);
  std::vector<double> scratch(signal::scratch_size(recipe));
  const signal::TableView view{table.data(), recipe.channels, recipe.samples};
  const signal::Status status = signal::generate(recipe, view, scratch);
  if (!status) throw std::invalid_argument(std::string("recipe: ") + status.message());
  return table;
}

}  // namespace excite::host
