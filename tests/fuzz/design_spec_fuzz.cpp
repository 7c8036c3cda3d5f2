// SPDX-License-Identifier: MIT
// Fuzzes design specs (host/design, parse_design_spec: prior knowledge and the design to make,
// TOML). Contracts checked: errors are std::invalid_argument whose message starts with the
// source name (any other exception escapes and is reported as a crash); an accepted spec
// names a design, has prior knowledge that passes validate_inputs (and validate() unless it
// is a plain multisine), and a multisine exactly when the design is "multisine".

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string_view>

#include "check.hpp"
#include "host/design/prior_knowledge.hpp"
#include "host/design/spec.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  constexpr std::string_view source = "fuzz-spec.toml";
  excite::host::DesignSpec spec;
  try {
    spec = excite::host::parse_design_spec(text, source);
    EXCITE_FUZZ_CHECK(!spec.design.empty(), "an accepted spec names its design");
    EXCITE_FUZZ_CHECK(spec.multisine.has_value() == (spec.design == "multisine"),
                      "a multisine section exactly for design = \"multisine\"");
  } catch (const std::invalid_argument& e) {
    if (!std::string_view(e.what()).starts_with(source)) std::fprintf(stderr, "%s\n", e.what());
    EXCITE_FUZZ_CHECK(std::string_view(e.what()).starts_with(source),
                      "an error message starts with the source name");
    return 0;
  }
  try {
    excite::host::validate_inputs(spec.prior);
    if (!spec.multisine) excite::host::validate(spec.prior);
  } catch (const std::invalid_argument&) {
    EXCITE_FUZZ_CHECK(false, "an accepted spec's prior knowledge fails validation");
  }
  return 0;
}
