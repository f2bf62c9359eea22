#include "pushpred/reading/text_files.hpp"

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "pushpred/core/error.hpp"

namespace pushpred {

std::string read_text_file(const std::filesystem::path& path, const std::string& what) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(about(path.string(), "is a folder, not " + what));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(about(path.string(), "cannot open " + what));
  std::stringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw InputError(about(path.string(), "cannot read " + what));
  return ss.str();
}

void for_each_csv_row(const std::string& text, const std::string& source,
                      const std::function<void(const std::string& line, const std::string& where)>& row) {
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    row(line, source + ":" + std::to_string(line_no));
  }
}

std::vector<Eigen::Vector2d> read_outline_csv_vertices(const std::filesystem::path& path) {
  std::vector<Eigen::Vector2d> vertices;
  bool first = true;
  for_each_csv_row(read_text_file(path, "an outline file"), path.string(),
                   [&](const std::string& line, const std::string& where) {
                     const bool header = first && line.rfind("x", 0) == 0;
                     first = false;
                     if (header) return;
                     const size_t comma = line.find(',');
                     if (comma == std::string::npos || line.find(',', comma + 1) != std::string::npos)
                       throw InputError(about(where, "expected two numbers x_m,y_m, got '" + plain_text(line) + "'"));
                     double xy[2];
                     const std::string field[2] = {line.substr(0, comma), line.substr(comma + 1)};
                     for (int k = 0; k < 2; ++k) {
                       try {
                         size_t used = 0;
                         xy[k] = std::stod(field[k], &used);
                         if (used != field[k].size()) throw std::invalid_argument(field[k]);
                       } catch (const std::exception&) {
                         throw InputError(about(where, "'" + plain_text(field[k]) + "' is not a number"));
                       }
                       if (!std::isfinite(xy[k]))
                         throw InputError(about(where, "'" + plain_text(field[k]) + "' is not finite"));
                     }
                     vertices.emplace_back(xy[0], xy[1]);
                   });
  return vertices;
}

}  // namespace pushpred
