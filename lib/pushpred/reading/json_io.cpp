// The dataset's JSON form: an object with arrays "tip_pose", "object_pose", "ft_wrench" of [t, a, b, c] rows.
#include <fstream>
#include <nlohmann/json.hpp>

#include "pushpred/core/error.hpp"
#include "pushpred/reading/recording.hpp"

namespace pushpred {
namespace {

Eigen::MatrixXd rows_from_json(const nlohmann::json& doc, const std::string& source, const char* name,
                               long long max_rows) {
  const std::string where = std::string("array '") + name + "'";
  if (!doc.contains(name)) throw InputError(about(source, where + " is missing"));
  const auto& arr = doc.at(name);
  if (!arr.is_array()) throw InputError(about(source, where + " is not an array"));
  if (arr.size() > 0 && static_cast<long long>(arr.size()) > max_rows)
    throw InputError(about(source, where + " has " + std::to_string(arr.size()) + " rows, more than the " +
                                       std::to_string(max_rows) + " a recording may hold"));
  Eigen::MatrixXd rows(static_cast<Eigen::Index>(arr.size()), 4);
  bool only_integers = arr.size() > 0;  // in columns 1 and 2 (x, y or fx, fy)
  for (size_t i = 0; i < arr.size(); ++i) {
    const auto& row = arr[i];
    if (!row.is_array() || row.size() != 4)
      throw InputError(about(source, where + " row " + std::to_string(i) + " does not hold 4 numbers [t, a, b, c]"));
    for (size_t j = 0; j < 4; ++j) {
      // JSON has no NaN or Inf; writers that emit them produce null or strings, both rejected here.
      if (!row[j].is_number())
        throw InputError(about(source, where + " row " + std::to_string(i) + " column " + std::to_string(j) +
                                           " is not a finite number"));
      if (j == 1 || j == 2) only_integers = only_integers && row[j].is_number_integer();
      rows(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = row[j].get<double>();
    }
  }
  // Positions in metres and forces in newtons written as integers have lost everything below a metre or a
  // newton (a writer that truncated them); the format stores them as real numbers.
  if (only_integers)
    throw InputError(about(source, where + " holds only integers in columns 1 and 2; the format stores real numbers "
                                           "(positions in metres, forces in newtons), integers would be truncated"));
  return rows;
}

/// nlohmann's message without its "[json.exception.parse_error.101] " tag, in plain text and bounded length.
std::string json_problem(const nlohmann::json::exception& e) {
  std::string what = e.what();
  if (what.rfind("[json.exception.", 0) == 0) {
    const auto end = what.find("] ");
    if (end != std::string::npos) what = what.substr(end + 2);
  }
  // Python's json.dump writes NaN and Infinity, which JSON does not have: the parser stops at their first letter.
  const auto last = what.rfind("invalid literal; last read: '");
  const bool non_finite = last != std::string::npos && what.size() >= 2 && what.back() == '\'' &&
                          (what[what.size() - 2] == 'N' || what[what.size() - 2] == 'I');
  what = plain_text(what);
  if (what.size() > 200) what = what.substr(0, 200) + "...";
  if (non_finite) what += " (NaN and Infinity are not JSON numbers; a recording holds finite numbers)";
  return what;
}

}  // namespace

Recording read_recording_json(const std::filesystem::path& path, const ReadOptions& options) {
  const std::string source = path.string();
  check_readable_file(path);
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(path, ec);
  if (!ec && static_cast<long long>(bytes) > options.max_json_bytes)
    throw InputError(about(source, "JSON file of " + std::to_string(bytes) + " bytes is larger than the " +
                                       std::to_string(options.max_json_bytes) + " a recording may be"));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(about(source, "cannot open file"));
  nlohmann::json doc;
  try {
    // Comments off; NaN/Infinity literals are not JSON and fail to parse; a UTF-8 byte-order mark is skipped.
    doc = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    // parse_error for syntax, out_of_range for a number like 1e400 that overflows a double.
    throw InputError(about(source, "malformed JSON: " + json_problem(e)));
  }
  if (!doc.is_object())
    throw InputError(about(source, std::string("JSON recording must be an object of three arrays "
                                               "(tip_pose, object_pose, ft_wrench), not ") +
                                       (doc.is_array() ? "an array" : doc.type_name())));
  Recording r;
  r.source = source;
  r.push = parse_push_filename(source);
  for (const char* name : {"tip_pose", "object_pose", "ft_wrench"})
    if (!doc.contains(name)) throw InputError(about(source, std::string("array '") + name + "' is missing"));
  const auto rows = [&](const char* name) { return rows_from_json(doc, source, name, options.max_rows); };
  r.tip_pose = condition_stream(source, "tip_pose", rows("tip_pose"), options, r.repairs);
  r.object_pose = condition_stream(source, "object_pose", rows("object_pose"), options, r.repairs);
  r.ft_wrench = condition_stream(source, "ft_wrench", rows("ft_wrench"), options, r.repairs);
  return r;
}

}  // namespace pushpred
