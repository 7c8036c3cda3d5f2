// SPDX-License-Identifier: MIT
#pragma once
// What a command's -o means for the rest of the command (host/README.md, "Output files"):
// with the data on standard output (-o -, /dev/stdout) every human line goes to stderr, so
// stdout carries only the data; and an output that is one of the command's inputs (same
// device and inode, whatever the names) is refused before anything is read or written.

#include <sys/stat.h>

#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "host/output/whole_file.hpp"

namespace excite::host::cli {

/// While alive, std::cout writes to stderr when `output` is standard output. The data itself
/// goes through WholeFile (C stdio), never std::cout.
class HumanTextAside {
 public:
  explicit HumanTextAside(const std::string& output) {
    if (!output.empty() && writes_to_stdout(output)) saved_ = std::cout.rdbuf(std::cerr.rdbuf());
  }
  ~HumanTextAside() {
    if (saved_ != nullptr) std::cout.rdbuf(saved_);
  }
  HumanTextAside(const HumanTextAside&) = delete;
  HumanTextAside& operator=(const HumanTextAside&) = delete;
  bool active() const { return saved_ != nullptr; }

 private:
  std::streambuf* saved_ = nullptr;
};

/// Throws "OUTPUT: cannot be written (it is the input INPUT, expected another file)" when
/// `output` exists and is the same file as one of `inputs`.
inline void refuse_output_among_inputs(const std::string& output,
                                       const std::vector<std::string>& inputs) {
  struct stat out {};
  if (output.empty() || output == "-" || ::stat(output.c_str(), &out) != 0) return;
  if (!S_ISREG(out.st_mode)) return;  // devices and FIFOs are written through
  for (const std::string& input : inputs) {
    struct stat in {};
    if (input.empty() || ::stat(input.c_str(), &in) != 0) continue;
    if (in.st_dev == out.st_dev && in.st_ino == out.st_ino) {
      throw std::invalid_argument(output + ": cannot be written (it is the input " + input +
                                  ", expected another file)");
    }
  }
}

/// identify's -o: not one of the runs, and not standard output together with --json (two
/// documents on one stream).
inline void check_identify_output(const std::string& output, const std::vector<std::string>& runs,
                                  bool json) {
  refuse_output_among_inputs(output, runs);
  if (json && !output.empty() && writes_to_stdout(output)) {
    throw std::invalid_argument("-o " + output +
                                " and --json both write to standard output, expected one of "
                                "the two");
  }
}

}  // namespace excite::host::cli
