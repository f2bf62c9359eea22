// The dataset's JSON form: an object with arrays "tip_pose", "object_pose", "ft_wrench" of [t, a, b, c] rows.
#include <fstream>
#include <nlohmann/json.hpp>

#include "pushpred/core/error.hpp"
#include "pushpred/reading/recording.hpp"

namespace pushpred {
namespace {

Eigen::MatrixXd rows_from_json(const nlohmann::json& doc, const std::string& source, const char* name) {
  const std::string where = std::string("array '") + name + "'";
  if (!doc.contains(name)) throw InputError(about(source, where + " is missing"));
  const auto& arr = doc.at(name);
  if (!arr.is_array()) throw InputError(about(source, where + " is not an array"));
  Eigen::MatrixXd rows(static_cast<Eigen::Index>(arr.size()), 4);
  for (size_t i = 0; i < arr.size(); ++i) {
    const auto& row = arr[i];
    if (!row.is_array() || row.size() != 4)
      throw InputError(about(source, where + " row " + std::to_string(i) + " does not hold 4 numbers [t, a, b, c]"));
    for (size_t j = 0; j < 4; ++j) {
      // JSON has no NaN or Inf; writers that emit them produce null or strings, both rejected here.
      if (!row[j].is_number())
        throw InputError(about(source, where + " row " + std::to_string(i) + " column " + std::to_string(j) +
                                           " is not a finite number"));
      rows(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = row[j].get<double>();
    }
  }
  return rows;
}

}  // namespace

Recording read_recording_json(const std::filesystem::path& path, const ReadOptions& options) {
  const std::string source = path.string();
  std::ifstream in(path);
  if (!in) throw InputError(about(source, "cannot open file"));
  nlohmann::json doc;
  try {
    // allow_exceptions and ignore_comments off; NaN/Infinity literals are not JSON and fail to parse.
    doc = nlohmann::json::parse(in);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(about(source, std::string("malformed JSON: ") + e.what()));
  }
  if (!doc.is_object()) throw InputError(about(source, "JSON recording must be an object of three arrays"));
  Recording r;
  r.source = source;
  r.push = parse_push_filename(source);
  r.tip_pose = condition_stream(source, "tip_pose", rows_from_json(doc, source, "tip_pose"), options, r.repairs);
  r.object_pose =
      condition_stream(source, "object_pose", rows_from_json(doc, source, "object_pose"), options, r.repairs);
  r.ft_wrench = condition_stream(source, "ft_wrench", rows_from_json(doc, source, "ft_wrench"), options, r.repairs);
  return r;
}

}  // namespace pushpred
