// SPDX-License-Identifier: MIT
// gnuplot's SVG compacted (issue 23 §3): empty groups go, a group's presentation attributes
// become a CSS class (lengths with their unit), transform and id stay, text is untouched.

#include <gtest/gtest.h>

#include "host/campaign/svg_compact.hpp"

namespace excite::host {
namespace {

const char* const kGnuplot =
    "<svg \n viewBox=\"0 0 10 10\"\n>\n<g id=\"gnuplot_canvas\">\n"
    "<g fill=\"none\" color=\"black\" stroke=\"currentColor\" stroke-width=\"0.50\">\n</g>\n"
    "<g fill=\"none\" color=\"gray\" stroke=\"gray\" stroke-width=\"1.00\">\n"
    "\t<path stroke='gray' d='M1,2 L3,4'/></g>\n"
    "<g fill=\"none\" color=\"gray\" stroke=\"gray\" stroke-width=\"1.00\">\n"
    "\t<g transform=\"translate(5.00,6.00)\" stroke=\"none\" fill=\"black\" font-size=\"9.00\">\n"
    "\t\t<text><tspan font-family=\"sans\" >a  b</tspan></text>\n\t</g>\n</g>\n"
    "</g>\n</svg>\n";

TEST(CompactGnuplotSvg, DropsEmptyGroupsAndMovesRepeatedAttributesIntoOneClass) {
  const std::string out = compact_gnuplot_svg(kGnuplot);
  EXPECT_EQ(out.find("color=\"black\""), std::string::npos) << out;  // the empty group
  EXPECT_NE(out.find("<style>"), std::string::npos) << out;
  EXPECT_NE(out.find("fill:none;color:gray;stroke:gray;stroke-width:1.00px;"), std::string::npos)
      << out;
  EXPECT_NE(out.find("font-size:9.00px;"), std::string::npos) << out;
  // The two groups with the same attributes share one rule; three groups carry a class.
  EXPECT_EQ(out.find("color:gray"), out.rfind("color:gray")) << out;
  int classes = 0;
  for (std::size_t at = 0; (at = out.find(" class=\"g", at)) != std::string::npos; ++at) ++classes;
  EXPECT_EQ(classes, 3) << out;
  EXPECT_NE(out.find("<g transform=\"translate(5.00,6.00)\" class="), std::string::npos) << out;
  EXPECT_NE(out.find("<tspan font-family=\"sans\" >a  b</tspan>"), std::string::npos) << out;
  EXPECT_NE(out.find("<path stroke='gray' d='M1,2 L3,4'/>"), std::string::npos) << out;
  EXPECT_NE(out.find("<g id=\"gnuplot_canvas\">"), std::string::npos) << out;
  EXPECT_EQ(out.find('\t'), std::string::npos) << out;
  EXPECT_LT(out.size(), std::string(kGnuplot).size());
}

TEST(CompactGnuplotSvg, PassesAnythingElseThrough) {
  EXPECT_EQ(compact_gnuplot_svg("<svg><path d='M0,0'/></svg>\n"), "<svg><path d='M0,0'/></svg>\n");
}

}  // namespace
}  // namespace excite::host
