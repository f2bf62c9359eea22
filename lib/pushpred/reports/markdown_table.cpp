#include "pushpred/reports/markdown_table.hpp"

#include <cstdio>

namespace pushpred {

std::string markdown_cell(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    if (c == '|')
      out += "\\|";
    else if (c == '\n' || c == '\r')
      out += ' ';
    else
      out += c;
  }
  return out;
}

std::string table_number(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  std::string out = text;
  // "-0.00" and the like: a negative number that rounds to zero (digits all zero, no other characters but the point
  // and an exponent).
  if (out.size() > 1 && out[0] == '-') {
    bool zero = true;
    for (std::size_t k = 1; k < out.size() && out[k] != 'e' && out[k] != 'E'; ++k)
      if (out[k] != '0' && out[k] != '.') zero = false;
    if (zero) out.erase(0, 1);
  }
  return out;
}

std::string markdown_row(const std::vector<std::string>& cells) {
  std::string row = "|";
  for (const auto& cell : cells) row += " " + markdown_cell(cell) + " |";
  return row + "\n";
}

std::string markdown_header(const std::vector<std::string>& cells, const std::vector<std::string>& alignment) {
  std::string separator = "|";
  for (std::size_t k = 0; k < cells.size(); ++k) separator += (k < alignment.size() ? alignment[k] : "---") + "|";
  return markdown_row(cells) + separator + "\n";
}

}  // namespace pushpred
