// SPDX-License-Identifier: MIT
#pragma once
// gnuplot's SVG without its bulk (issue 23 §3): gnuplot wraps every grid line, tic and label
// in a group repeating the same presentation attributes, and leaves many groups empty. The
// compacted file draws the same picture: empty groups are dropped, each distinct set of a
// group's presentation attributes becomes one CSS class in a <style> (transform and id stay
// attributes), and the indentation between tags goes.

#include <string>

namespace excite::host {

/// The same SVG, smaller. Input is gnuplot's svg terminal output; anything it does not
/// recognise passes through unchanged.
std::string compact_gnuplot_svg(const std::string& svg);

}  // namespace excite::host
