// SPDX-License-Identifier: MIT
// host/montecarlo/html_page.hpp: the report's one place of HTML escaping. Markup is what the
// code writes as literals; every std::string is text, escaped whatever it holds.

#include "host/output/html_page.hpp"

#include <gtest/gtest.h>

#include <string>

namespace excite::host {
namespace {

TEST(HtmlPage, StringsAreTextAndLiteralsAreMarkup) {
  HtmlPage h;
  const std::string name = "<script>alert('x')</script> & \"q\"";
  h << "<tr class='dir'><td>" << name << "</td><td>" << 42 << ' ' << 2.5 << "</td></tr>";
  EXPECT_EQ(h.str(),
            "<tr class='dir'><td>&lt;script&gt;alert(&#39;x&#39;)&lt;/script&gt; &amp; "
            "&quot;q&quot;</td><td>42 2.5</td></tr>");
}

TEST(HtmlPage, CodeMarkupIsWrittenAsIs) {
  HtmlPage h;
  const char* style = "a>b{color:red}";
  h << "<style>" << CodeMarkup{style} << "</style>" << std::string(style);
  EXPECT_EQ(h.str(), "<style>a>b{color:red}</style>a&gt;b{color:red}");
}

}  // namespace
}  // namespace excite::host
