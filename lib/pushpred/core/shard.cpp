#include "pushpred/core/shard.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <numeric>
#include <set>
#include <sstream>

#include "pushpred/core/error.hpp"
#include "pushpred/core/output_files.hpp"
#include "pushpred/core/version.hpp"

namespace fs = std::filesystem;

namespace pushpred {
namespace {

constexpr int kPartialFormat = 1;
constexpr const char* kManifestName = "partial.json";

std::string dump(const nlohmann::json& doc, int indent) {
  return doc.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

/// A non-negative decimal integer of at most 7 digits, or nothing.
std::optional<int> small_count(const std::string& text) {
  if (text.empty() || text.size() > 7) return std::nullopt;
  for (char c : text)
    if (c < '0' || c > '9') return std::nullopt;
  return std::stoi(text);
}

std::string part_error(const PartialOutput& part, const std::string& what) {
  return about(plain_text(part.name), what);
}

/// True when `name` is a path inside an output folder: relative, no "..".
bool relative_inside(const std::string& name) {
  const fs::path p(name);
  bool ok = !name.empty() && p.is_relative();
  for (const auto& part : p)
    if (part == "..") ok = false;
  return ok;
}

/// A file an item lists must stay inside the output.
void require_relative_inside(const std::string& name) {
  if (!relative_inside(name))
    throw InputError("its item lists the file '" + plain_text(name) + "', which is not a path inside the output");
}

constexpr char kBase64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

std::string to_base64(const std::string& bytes) {
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t v = 0;
    for (std::size_t k = 0; k < 3; ++k)
      v = (v << 8) | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0u);
    for (std::size_t k = 0; k < 4; ++k) out += k <= n ? kBase64[(v >> (18 - 6 * k)) & 63] : '=';
  }
  return out;
}

std::string from_base64(const std::string& text, const std::string& part, const std::string& file) {
  const auto bad = [&] { return InputError(about(plain_text(part), "its file " + plain_text(file) + " is garbled")); };
  if (text.size() % 4 != 0) throw bad();
  std::string out;
  out.reserve(text.size() / 4 * 3);
  for (std::size_t i = 0; i < text.size(); i += 4) {
    std::uint32_t v = 0;
    int pad = 0;
    for (std::size_t k = 0; k < 4; ++k) {
      const char c = text[i + k];
      const char* at = c == '\0' ? nullptr : std::strchr(kBase64, c);
      if (c == '=' && i + 4 == text.size() && k >= 2) {
        ++pad;
        v <<= 6;
        continue;
      }
      if (!at || pad > 0) throw bad();
      v = (v << 6) | static_cast<std::uint32_t>(at - kBase64);
    }
    out += static_cast<char>((v >> 16) & 255);
    if (pad < 2) out += static_cast<char>((v >> 8) & 255);
    if (pad < 1) out += static_cast<char>(v & 255);
  }
  return out;
}

}  // namespace

nlohmann::json exact_number_json(double x) {
  if (std::isfinite(x)) return x;
  return std::isnan(x) ? "nan" : (x > 0 ? "inf" : "-inf");
}

double exact_number(const nlohmann::json& j) {
  if (j.is_number()) return j.get<double>();
  if (j.is_string()) {
    const std::string s = j.get<std::string>();
    if (s == "nan") return std::numeric_limits<double>::quiet_NaN();
    if (s == "inf") return std::numeric_limits<double>::infinity();
    if (s == "-inf") return -std::numeric_limits<double>::infinity();
  }
  throw InputError("'" + plain_text(j.dump()) + "' is not a number");
}

ShardSpec parse_shard_spec(const std::string& text) {
  const std::string shown = "--shard '" + plain_text(text) + "'";
  const auto slash = text.find('/');
  if (slash == std::string::npos)
    throw InputError(shown + ": expected I/N, share I of N (e.g. 1/4), 1 <= I <= N");
  const auto index = small_count(text.substr(0, slash));
  const auto count = small_count(text.substr(slash + 1));
  if (!index || !count)
    throw InputError(shown + ": expected I/N with I and N whole numbers (e.g. 1/4), 1 <= I <= N");
  if (*count < 1 || *count > 1000000) throw InputError(shown + ": N must be between 1 and 1000000");
  if (*index < 1 || *index > *count)
    throw InputError(shown + ": I must be between 1 and N (" + std::to_string(*count) + "); shards count from 1");
  return {*index, *count};
}

std::vector<std::size_t> shard_positions(const std::vector<fs::path>& inputs, const ShardSpec& shard) {
  std::vector<std::size_t> order(inputs.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return inputs[a].string() < inputs[b].string(); });
  std::vector<std::size_t> mine;
  for (std::size_t k = 0; k < order.size(); ++k)
    if (static_cast<int>(k % static_cast<std::size_t>(shard.count)) == shard.index - 1) mine.push_back(order[k]);
  std::sort(mine.begin(), mine.end());
  return mine;
}

std::string inputs_fingerprint(const std::vector<fs::path>& inputs) {
  std::uint64_t h = 1469598103934665603ull;
  const auto add = [&h](unsigned char c) {
    h ^= c;
    h *= 1099511628211ull;
  };
  for (const auto& p : inputs) {
    for (unsigned char c : p.string()) add(c);
    add(0);  // a separator no path holds
  }
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h));
  return text;
}

void FileSink::write(const std::string& name, const std::string& text) {
  if (out_) {
    write_text_atomically(out_->path(name), text);
    return;
  }
  const std::lock_guard<std::mutex> lock(mutex_);
  files_[name] = text;
}

nlohmann::json partial_manifest(const std::string& command, const ShardSpec& shard, const std::vector<fs::path>& inputs,
                                const nlohmann::json& options, std::vector<PartialItem> items) {
  return partial_manifest(command, shard, inputs.size(), inputs_fingerprint(inputs), options, std::move(items));
}

nlohmann::json partial_manifest(const std::string& command, const ShardSpec& shard, std::size_t count,
                                const std::string& fingerprint, const nlohmann::json& options,
                                std::vector<PartialItem> items) {
  nlohmann::json list = nlohmann::json::array();
  for (auto& item : items) {
    nlohmann::json entry = {{"index", item.index}};
    if (item.result) {
      entry["result"] = std::move(*item.result);
      item.result.reset();
      entry["files"] = item.files;
    } else if (item.failure) {
      entry["failure"] = {{"source", item.failure->source}, {"reason", item.failure->reason}};
    }
    list.push_back(std::move(entry));
  }
  return {{"pushpred_partial", kPartialFormat},
          {"pushpred_version", kVersion},
          {"command", command},
          {"shard", {{"index", shard.index}, {"count", shard.count}}},
          {"inputs", {{"count", count}, {"fingerprint", fingerprint}}},
          {"options", options},
          {"items", list}};
}

void write_partial_output(StagedOutput& out, const nlohmann::json& manifest) {
  write_text_atomically(out.path(kManifestName), json_file_text(manifest));
  out.commit();
}

namespace {

constexpr int kItemsDepth = 1, kItemDepth = 2;  // {"items": [ {item}, ... ]}: the key's and an item's depth

/// Sets `item`'s result aside as compact text in `texts`, leaving its position there in its place.
void set_result_aside(nlohmann::json& item, std::vector<std::string>& texts) {
  if (!item.is_object()) return;
  const auto it = item.find("result");
  if (it == item.end()) return;
  texts.push_back(dump(*it, -1));
  *it = texts.size() - 1;
}

}  // namespace

PartialOutput partial_output(std::string name, nlohmann::json manifest,
                             std::function<std::string(const std::string&)> read_file) {
  PartialOutput part;
  part.name = std::move(name);
  part.manifest = std::move(manifest);
  part.read_file = std::move(read_file);
  if (part.manifest.is_object() && part.manifest.contains("items") && part.manifest["items"].is_array())
    for (auto& item : part.manifest["items"]) set_result_aside(item, part.result_texts);
  return part;
}

PartialOutput read_partial_output(const fs::path& folder, const std::string& shown) {
  const std::string name = shown.empty() ? folder.string() : shown;
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw InputError(about(plain_text(name), fs::exists(folder, ec) ? "not a folder (a merge reads the folders "
                                                                      "that --shard runs wrote)"
                                                                    : "no such folder"));
  const fs::path manifest_path = folder / kManifestName;
  std::ifstream in(manifest_path, std::ios::binary);
  if (!in)
    throw InputError(about(plain_text(name), std::string("no ") + kManifestName +
                                                 ": not a partial output of pushpred (make them with --shard I/N)"));
  PartialOutput part;
  part.name = name;
  // Parsed as a stream: each item's result becomes text as soon as it is complete (set_result_aside).
  std::string top_key;
  const auto set_aside = [&](int depth, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
    if (event == nlohmann::json::parse_event_t::key && depth == kItemsDepth) top_key = parsed.get<std::string>();
    else if (event == nlohmann::json::parse_event_t::object_end && depth == kItemDepth && top_key == "items")
      set_result_aside(parsed, part.result_texts);
    return true;
  };
  try {
    part.manifest = nlohmann::json::parse(in, set_aside);
  } catch (const std::exception& e) {
    throw InputError(about(plain_text(manifest_path.string()), std::string("not valid JSON: ") + e.what()));
  }
  part.read_file = [folder, name](const std::string& relative) {
    std::ifstream f(folder / relative, std::ios::binary);
    if (!f) throw InputError(about(plain_text(name), "its file " + plain_text(relative) + " is missing"));
    std::ostringstream s;
    s << f.rdbuf();
    return s.str();
  };
  return part;
}

std::string partial_bundle(const nlohmann::json& manifest, std::map<std::string, std::string> files) {
  // Written as text one file at a time, each dropped once encoded: a tree of the encoded files and its dump would
  // hold every file twice more (issue 12). Base64: a file may be binary (a plot), JSON text is UTF-8.
  std::string text = "{\"manifest\":" + dump(manifest, -1) + ",\"files\":{";
  std::size_t size = text.size() + 2;
  for (const auto& [name, bytes] : files) size += name.size() + 8 + (bytes.size() + 2) / 3 * 4;  // names' escapes aside
  text.reserve(size);  // grown by doubling, the text would take up to twice its size at its last step
  const char* separator = "";
  while (!files.empty()) {
    auto node = files.extract(files.begin());
    text += separator;
    separator = ",";
    text += dump(nlohmann::json(node.key()), -1);
    text += ":\"";
    text += to_base64(node.mapped());
    text += '"';
  }
  text += "}}";  // in place: `text + "}}"` would copy the whole text and grow the copy past its size
  return text;
}

void unpack_partial_bundle(const std::string& name, const std::string& bundle, const fs::path& folder) {
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec) throw InputError(about(plain_text(folder.string()), "cannot create folder: " + ec.message()));
  const auto write_file = [&](const std::string& relative, const nlohmann::json& encoded) {
    if (!relative_inside(relative))
      throw InputError(
          about(plain_text(name), "its file '" + plain_text(relative) + "' is not a path inside the output"));
    if (!encoded.is_string())
      throw InputError(about(plain_text(name), "its file " + plain_text(relative) + " is garbled"));
    const fs::path path = folder / relative;
    fs::create_directories(path.parent_path(), ec);
    if (ec) throw InputError(about(plain_text(path.parent_path().string()), "cannot create folder: " + ec.message()));
    write_text_atomically(path, from_base64(encoded.get_ref<const std::string&>(), name, relative));
  };
  // Parsed as a stream: each file is written as soon as it is read and dropped from the tree (the callback returns
  // false), so that rank 0 holds the bundle's text and one file, not every file decoded twice over.
  using Event = nlohmann::json::parse_event_t;
  std::string top_key, file_name;
  bool in_files = false;
  const auto write_as_read = [&](int depth, Event event, nlohmann::json& parsed) {
    if (depth == 1 && event == Event::key) {
      top_key = parsed.get<std::string>();
    } else if (depth == 1 && event == Event::object_start) {
      in_files = top_key == "files";
    } else if (depth == 1 && event == Event::object_end) {
      in_files = false;
    } else if (in_files && depth == 2 && event == Event::key) {
      file_name = parsed.get<std::string>();
    } else if (in_files && depth == 2 && (event == Event::value || event == Event::object_end ||
                                          event == Event::array_end)) {
      write_file(file_name, parsed);
      return false;
    }
    return true;
  };
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(bundle, write_as_read);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(about(plain_text(name), std::string("its partial output is not readable: ") + e.what()));
  }
  if (!doc.is_object() || !doc.contains("manifest") || !doc["manifest"].is_object() || !doc.contains("files") ||
      !doc["files"].is_object())
    throw InputError(about(plain_text(name), "its partial output is not readable: not a partial bundle"));
  write_text_atomically(folder / kManifestName, json_file_text(doc["manifest"]));
}

nlohmann::json MergedItem::result() const {
  if (!result_json) throw InputError("it lists no result");
  return nlohmann::json::parse(*result_json);
}

MergedParts check_partial_outputs(std::vector<PartialOutput> given) {
  if (given.empty()) throw InputError("merge: no partial outputs given");
  MergedParts merged;
  merged.parts = std::move(given);
  std::vector<PartialOutput>& parts = merged.parts;
  const PartialOutput& first = parts.front();
  std::size_t count = 0;
  std::string fingerprint;
  int shards = 0;
  std::map<int, const PartialOutput*> seen;
  std::vector<std::optional<MergedItem>> items;
  for (auto& part : parts) {
    const auto& m = part.manifest;
    try {
      if (!m.is_object() || m.value("pushpred_partial", 0) != kPartialFormat)
        throw InputError("not a partial output of pushpred (no \"pushpred_partial\": 1)");
      const std::string command = m.at("command").get<std::string>();
      const int index = m.at("shard").at("index").get<int>();
      const int n = m.at("shard").at("count").get<int>();
      const std::size_t inputs = m.at("inputs").at("count").get<std::size_t>();
      const std::string print = m.at("inputs").at("fingerprint").get<std::string>();
      const std::string version = m.at("pushpred_version").get<std::string>();
      if (n < 1 || index < 1 || index > n) throw InputError("its shard " + std::to_string(index) + "/" +
                                                            std::to_string(n) + " is not a share I/N");
      if (&part == &first) {
        merged.command = command;
        merged.options = m.at("options");
        count = inputs;
        fingerprint = print;
        shards = n;
        items.resize(count);
      } else {
        const std::string other = " than " + plain_text(first.name);
        if (command != merged.command)
          throw InputError("it is a partial output of `" + command + "`, not of `" + merged.command + "` as " +
                           plain_text(first.name));
        if (version != first.manifest.at("pushpred_version").get<std::string>())
          throw InputError("written by pushpred " + version + ", a different version" + other);
        if (n != shards)
          throw InputError("it is shard " + std::to_string(index) + "/" + std::to_string(n) + ", but " +
                           plain_text(first.name) + " was split into " + std::to_string(shards));
        if (inputs != count || print != fingerprint)
          throw InputError("its run was given other inputs" + other + " (" + std::to_string(inputs) + " against " +
                           std::to_string(count) + ", or another list or order): give every shard the same inputs");
        if (m.at("options") != merged.options)
          throw InputError("its run had other options" + other + ": give every shard the same options");
      }
      if (seen.count(index))
        throw InputError("it is shard " + std::to_string(index) + "/" + std::to_string(n) + ", as is " +
                         plain_text(seen[index]->name));
      seen[index] = &part;
      for (const auto& entry : m.at("items")) {
        MergedItem mi;
        mi.part = &part;
        mi.index = entry.at("index").get<std::size_t>();
        if (mi.index >= count)
          throw InputError("its item " + std::to_string(mi.index) + " is beyond the " + std::to_string(count) +
                           " inputs");
        if (entry.contains("result")) {
          // Its position among the part's result texts (partial_output, read_partial_output).
          const std::size_t at = entry.at("result").get<std::size_t>();
          if (at >= part.result_texts.size()) throw InputError("its result " + std::to_string(at) + " is not held");
          mi.result_json = std::move(part.result_texts[at]);
          mi.files = entry.at("files").get<std::vector<std::string>>();
          for (const auto& f : mi.files) require_relative_inside(f);
        } else {
          const auto& f = entry.at("failure");
          mi.failure = BatchFailure{f.at("source").get<std::string>(), f.at("reason").get<std::string>()};
        }
        if (items[mi.index])
          throw InputError("input " + std::to_string(mi.index + 1) + " is also in " +
                           plain_text(items[mi.index]->part->name));
        items[mi.index] = std::move(mi);
      }
    } catch (const InputError& e) {
      throw InputError(part_error(part, e.what()));
    } catch (const nlohmann::json::exception& e) {
      throw InputError(part_error(part, std::string("partial.json is not pushpred's partial format: ") + e.what()));
    }
  }
  std::string missing;
  for (int i = 1; i <= shards; ++i)
    if (!seen.count(i)) missing += (missing.empty() ? "" : ", ") + std::to_string(i) + "/" + std::to_string(shards);
  if (!missing.empty())
    throw InputError("merge: shard" + std::string(missing.find(',') == std::string::npos ? " " : "s ") + missing +
                     " missing: give the partial output of every shard");
  for (std::size_t k = 0; k < items.size(); ++k) {
    if (!items[k])
      throw InputError("merge: input " + std::to_string(k + 1) + " of " + std::to_string(count) +
                       " is in no part (a part was changed after its run?)");
    merged.items.push_back(std::move(*items[k]));
  }
  return merged;
}

}  // namespace pushpred
