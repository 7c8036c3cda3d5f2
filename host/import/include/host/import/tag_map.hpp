// SPDX-License-Identifier: MIT
#pragma once
// The tag map file (`excite import --map TAGS.toml`): which historian tags are MVs and CVs,
// and the run log's name and unit for each.
//
//   [[mv]]
//   tag = "FIC-101.SP"   # the historian column (required)
//   name = "L"           # the run log's channel name (default: the tag)
//   unit = "kmol/min"    # default "-"
//   [[cv]]
//   tag = "AI-201.PV"
//   name = "xD"
//   unit = "mol/mol"
//
// Order in the file is the order of the run log's inputs and outputs. Unknown keys are
// errors; errors name the file, line and column, the key and what was expected.

#include <string>
#include <string_view>

#include "host/import/import_run.hpp"

namespace excite::host::historian {

struct TagMap {
  std::vector<TagSpec> mvs;
  std::vector<TagSpec> cvs;
};

TagMap parse_tag_map(std::string_view toml_text, std::string_view source_name);
TagMap read_tag_map(const std::string& path);

}  // namespace excite::host::historian
