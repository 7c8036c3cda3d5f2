// SPDX-License-Identifier: MIT
// Fuzzes the element grammar (sim/lti, parse_element: "4.09 e^-1.3s / ((33s+1)(8.3s+1))")
// and discretises what parses (discretise_zoh, at T = 1 and 0.1 min). Contracts checked:
// a rejection is an ElementSyntaxError with a message and a position inside the text (any
// other exception escapes and is reported as a crash); every parsed term passes check_term;
// discretisation either refuses with std::invalid_argument (a delay beyond kMaxDelaySamples)
// or gives finite coefficients within capacity, a[0] = 1 and a delay ≥ 0.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string_view>

#include "check.hpp"
#include "sim/lti/discretise.hpp"
#include "sim/lti/parse_element.hpp"

namespace {

using excite::sim::DiscreteTerm;

void check_discrete(const DiscreteTerm& d) {
  EXCITE_FUZZ_CHECK(d.delay_samples >= 0, "negative delay");
  EXCITE_FUZZ_CHECK(d.nb >= 1 && d.nb <= excite::sim::kMaxCoefficients && d.na >= 1 &&
                        d.na <= excite::sim::kMaxCoefficients,
                    "coefficient counts beyond capacity");
  EXCITE_FUZZ_CHECK(d.a[0] == 1.0, "a[0] must be 1");
  for (int i = 0; i < d.nb; ++i) {
    EXCITE_FUZZ_CHECK(std::isfinite(d.b[static_cast<std::size_t>(i)]), "b not finite");
  }
  for (int i = 0; i < d.na; ++i) {
    EXCITE_FUZZ_CHECK(std::isfinite(d.a[static_cast<std::size_t>(i)]), "a not finite");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  excite::sim::Element element;
  try {
    element = excite::sim::parse_element(text, "fuzz");
  } catch (const excite::sim::ElementSyntaxError& e) {
    EXCITE_FUZZ_CHECK(std::string_view(e.what()).size() > 0, "a rejection names its reason");
    EXCITE_FUZZ_CHECK(e.position() <= size, "error position beyond the text");
    return 0;
  }
  for (const excite::sim::Term& term : element.terms()) {
    EXCITE_FUZZ_CHECK(excite::sim::check_term(term).empty(), "a parsed term fails check_term");
    for (const double sample_time_min : {1.0, 0.1}) {
      try {
        check_discrete(excite::sim::discretise_zoh(term, sample_time_min));
      } catch (const std::invalid_argument&) {
        // refused with a message: a delay too long for the sample time
      }
    }
  }
  return 0;
}
