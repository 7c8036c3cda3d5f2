// SPDX-License-Identifier: MIT
#include "host/campaign/svg_compact.hpp"

#include <cctype>
#include <map>
#include <vector>

namespace excite::host {
namespace {

struct Attribute {
  std::string name, value;
};

// The attributes of a tag's text after its name ("a='1' b=\"2\""); empty when it does not
// parse as plain name=quoted-value pairs.
bool parse_attributes(const std::string& text, std::vector<Attribute>& out) {
  std::size_t i = 0;
  while (true) {
    while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
    if (i == text.size()) return true;
    const std::size_t eq = text.find('=', i);
    if (eq == std::string::npos) return false;
    Attribute a{text.substr(i, eq - i), {}};
    while (!a.name.empty() && std::isspace(static_cast<unsigned char>(a.name.back())))
      a.name.pop_back();
    std::size_t q = eq + 1;
    while (q < text.size() && std::isspace(static_cast<unsigned char>(text[q]))) ++q;
    if (q == text.size() || (text[q] != '"' && text[q] != '\'')) return false;
    const std::size_t end = text.find(text[q], q + 1);
    if (end == std::string::npos || a.name.empty()) return false;
    a.value = text.substr(q + 1, end - q - 1);
    out.push_back(a);
    i = end + 1;
  }
}

bool numeric(const std::string& v) {
  if (v.empty()) return false;
  for (const char c : v) {
    if (!std::isdigit(static_cast<unsigned char>(c)) && c != '.') return false;
  }
  return true;
}

// A presentation attribute as a CSS declaration; lengths get their unit (CSS needs one).
std::string declaration(const Attribute& a) {
  const bool length = a.name == "stroke-width" || a.name == "font-size";
  return a.name + ':' + a.value + (length && numeric(a.value) ? "px" : "") + ';';
}

}  // namespace

std::string compact_gnuplot_svg(const std::string& svg) {
  std::string out;
  out.reserve(svg.size());
  std::vector<std::size_t> open;             // where each open <g …> starts in `out`
  std::vector<std::size_t> content;          // where its content starts
  std::map<std::string, std::string> rules;  // declarations → class name
  std::size_t i = 0;
  while (i < svg.size()) {
    // Indentation between tags: a newline followed by tabs or spaces before '<'.
    if (svg[i] == '\n') {
      std::size_t j = i + 1;
      while (j < svg.size() && (svg[j] == '\t' || svg[j] == ' ')) ++j;
      if (j < svg.size() && svg[j] == '<') {
        out += '\n';
        i = j;
        continue;
      }
    }
    if (svg.compare(i, 3, "<g ") == 0 || svg.compare(i, 3, "<g>") == 0) {
      const std::size_t end = svg.find('>', i);
      if (end == std::string::npos) break;
      const std::string inner = svg.substr(i + 2, end - i - 2);
      std::vector<Attribute> attributes;
      open.push_back(out.size());
      if (!inner.empty() && inner.back() != '/' && parse_attributes(inner, attributes)) {
        std::string kept, css;
        for (const Attribute& a : attributes) {
          if (a.name == "transform" || a.name == "id" || a.name == "class" ||
              a.name.find(':') != std::string::npos) {
            kept += ' ' + a.name + "=\"" + a.value + '"';
          } else {
            css += declaration(a);
          }
        }
        std::string tag = "<g" + kept;
        if (!css.empty()) {
          auto [it, added] = rules.emplace(css, "g" + std::to_string(rules.size()));
          tag += " class=\"" + it->second + '"';
        }
        out += tag + '>';
      } else {
        out.append(svg, i, end - i + 1);
      }
      content.push_back(out.size());
      i = end + 1;
      continue;
    }
    if (svg.compare(i, 4, "</g>") == 0 && !open.empty()) {
      const std::size_t start = open.back(), body = content.back();
      open.pop_back();
      content.pop_back();
      bool empty = true;
      for (std::size_t k = body; k < out.size() && empty; ++k)
        empty = std::isspace(static_cast<unsigned char>(out[k])) != 0;
      if (empty) {
        out.resize(start);  // an empty group draws nothing
      } else {
        out += "</g>";
      }
      i += 4;
      continue;
    }
    out += svg[i++];
  }
  if (rules.empty()) return out;
  std::string style = "<style>";
  for (const auto& [css, name] : rules) style += "g." + name + '{' + css + '}';
  style += "</style>\n";
  const std::size_t canvas = out.find("<g id=\"gnuplot_canvas\"");
  if (canvas != std::string::npos) return out.insert(canvas, style);
  const std::size_t root = out.find("<svg");
  const std::size_t root_end = root == std::string::npos ? root : out.find('>', root);
  if (root_end == std::string::npos) return svg;  // not an SVG we know: unchanged
  return out.insert(root_end + 1, style);
}

}  // namespace excite::host
