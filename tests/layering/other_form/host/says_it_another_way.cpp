// SPDX-License-Identifier: MIT
// A fixture for check_message_form.py: a message in the form the project no longer uses.
#include <stdexcept>

void refuse() {
  throw std::invalid_argument("channels: expected >= 1");
}
