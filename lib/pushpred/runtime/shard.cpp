#include "pushpred/runtime/shard.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <numeric>
#include <set>
#include <sstream>

#include "pushpred/core/error.hpp"
#include "pushpred/core/version.hpp"
#include "pushpred/runtime/output_files.hpp"

namespace fs = std::filesystem;

namespace pushpred {
namespace {

constexpr int kPartialFormat = 1;

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

/// Writes `bytes` at `relative` under `folder`, making the subfolders it needs.
void write_under(const fs::path& folder, const std::string& relative, const char* bytes, std::size_t size) {
  const fs::path path = folder / relative;
  std::error_code ec;
  fs::create_directories(path.parent_path(), ec);
  if (ec) throw InputError(about(plain_text(path.parent_path().string()), "cannot create folder: " + ec.message()));
  write_file_atomically(path, [&](std::ostream& out) { out.write(bytes, static_cast<std::streamsize>(size)); });
}

/// A file an item lists must stay inside the output.
void require_relative_inside(const std::string& name) {
  if (!relative_inside(name))
    throw InputError("its item lists the file '" + plain_text(name) + "', which is not a path inside the output");
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
  if (slash == std::string::npos) throw InputError(shown + ": expected I/N, share I of N (e.g. 1/4), 1 <= I <= N");
  const auto index = small_count(text.substr(0, slash));
  const auto count = small_count(text.substr(slash + 1));
  if (!index || !count) throw InputError(shown + ": expected I/N with I and N whole numbers (e.g. 1/4), 1 <= I <= N");
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
  if (out_)
    write_text_atomically(out_->path(name), text);
  else
    write_under(folder_, name, text.data(), text.size());
  const std::lock_guard<std::mutex> lock(mutex_);
  names_.insert(name);
}

std::filesystem::path FileSink::path(const std::string& name) const { return out_ ? out_->path(name) : folder_ / name; }

std::vector<std::string> FileSink::names() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return {names_.begin(), names_.end()};
}

std::string partial_result_text(const nlohmann::json& result) { return dump(result, -1); }

std::string partial_manifest(const std::string& command, const ShardSpec& shard, const std::vector<fs::path>& inputs,
                             const nlohmann::json& options, std::vector<PartialItem> items) {
  return partial_manifest(command, shard, inputs.size(), inputs_fingerprint(inputs), options, std::move(items));
}

PartialManifestWriter::PartialManifestWriter(std::ostream& out, const std::string& command, const ShardSpec& shard,
                                             std::size_t count, const std::string& fingerprint,
                                             const nlohmann::json& options)
    : out_(out) {
  // Each item is written on a line of its own in the items' place, its result's text put in as it is (a tree of
  // every result would take several times the text).
  JsonTextAround text = json_file_text_around({{"pushpred_partial", kPartialFormat},
                                               {"pushpred_version", kVersion},
                                               {"command", command},
                                               {"shard", {{"index", shard.index}, {"count", shard.count}}},
                                               {"inputs", {{"count", count}, {"fingerprint", fingerprint}}},
                                               {"options", options}},
                                              "items");
  out_ << text.before << '[';
  tail_ = std::move(text.after);
}

void PartialManifestWriter::add(PartialItem item) {
  nlohmann::json entry = {{"index", item.index}};
  if (item.result_json)
    entry["files"] = item.files;
  else if (item.failure) {
    entry["failure"] = {{"source", item.failure->source}, {"reason", item.failure->reason}};
    if (item.failure->skipped) entry["failure"]["skipped"] = true;
  }
  std::string line = dump(entry, -1);
  out_ << (first_ ? "\n    " : ",\n    ");
  first_ = false;
  if (item.result_json) {
    line.pop_back();  // the closing brace: the result goes last
    out_ << line << ",\"result\":" << *item.result_json << '}';
  } else {
    out_ << line;
  }
}

void PartialManifestWriter::finish() { out_ << (first_ ? "]" : "\n  ]") << tail_; }

std::string partial_manifest(const std::string& command, const ShardSpec& shard, std::size_t count,
                             const std::string& fingerprint, const nlohmann::json& options,
                             std::vector<PartialItem> items) {
  std::ostringstream out;
  PartialManifestWriter writer(out, command, shard, count, fingerprint, options);
  for (auto& item : items) {
    writer.add(std::move(item));
    item = PartialItem{};
  }
  writer.finish();
  return out.str();
}

void write_partial_output(StagedOutput& out, const std::string& manifest) {
  write_text_atomically(out.path(kPartialManifestName), manifest);
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

/// Where an item's result lies in partial.json: from just after its key (then blanks and the colon) to its end.
struct ResultSpan {
  std::uint64_t from = 0, to = 0;
};

/// The text of `span` in the file at `path`, without the colon and blanks before the value.
std::string read_span(const fs::path& path, const ResultSpan& span) {
  std::ifstream in(path, std::ios::binary);
  std::string text(static_cast<std::size_t>(span.to - span.from), '\0');
  if (!in.seekg(static_cast<std::streamoff>(span.from)) ||
      !in.read(text.data(), static_cast<std::streamsize>(text.size())))
    throw InputError(about(plain_text(path.string()), "changed or gone while merging"));
  const std::size_t value = text.find_first_not_of(" \t\r\n:");
  text.erase(0, value == std::string::npos ? text.size() : value);
  return text;
}

}  // namespace

PartialOutput partial_output(std::string name, nlohmann::json manifest,
                             std::function<std::string(const std::string&)> read_file) {
  PartialOutput part;
  part.name = std::move(name);
  part.manifest = std::move(manifest);
  part.read_file = std::move(read_file);
  auto texts = std::make_shared<std::vector<std::string>>();
  if (part.manifest.is_object() && part.manifest.contains("items") && part.manifest["items"].is_array())
    for (auto& item : part.manifest["items"]) set_result_aside(item, *texts);
  part.results = texts->size();
  part.result_text = [texts](std::size_t k) { return texts->at(k); };
  return part;
}

PartialOutput read_partial_output(const fs::path& folder, const std::string& shown) {
  const std::string name = shown.empty() ? folder.string() : shown;
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw InputError(about(plain_text(name), fs::exists(folder, ec) ? "not a folder (a merge reads the folders "
                                                                      "that --shard runs wrote)"
                                                                    : "no such folder"));
  const fs::path manifest_path = folder / kPartialManifestName;
  std::ifstream in(manifest_path, std::ios::binary);
  if (!in)
    throw InputError(about(plain_text(name), std::string("no ") + kPartialManifestName +
                                                 ": not a partial output of pushpred (make them with --shard I/N)"));
  PartialOutput part;
  part.name = name;
  // Parsed as a stream. nlohmann's parser takes one character at a time from the file and reports a key as soon as
  // its closing quote is read and an object's or array's end as soon as its bracket is, so the file's position at
  // those events brackets each item's result, which is then dropped from the tree. A result that is neither an
  // object nor an array (no end event) is kept as text.
  const auto position = [&] {
    return static_cast<std::uint64_t>(in.rdbuf()->pubseekoff(0, std::ios::cur, std::ios::in));
  };
  auto spans = std::make_shared<std::vector<ResultSpan>>();
  auto kept = std::make_shared<std::map<std::size_t, std::string>>();  // results kept as text, by position
  std::string top_key, item_key;
  ResultSpan span;
  bool span_closed = false;
  using event_t = nlohmann::json::parse_event_t;
  const auto set_aside = [&](int depth, event_t event, nlohmann::json& parsed) {
    if (event == event_t::key && depth == kItemsDepth) {
      top_key = parsed.get<std::string>();
    } else if (top_key != "items") {
      return true;
    } else if (event == event_t::key && depth == kItemDepth + 1) {
      item_key = parsed.get<std::string>();
      if (item_key == "result") {
        span = {position(), 0};
        span_closed = false;
      }
    } else if ((event == event_t::object_end || event == event_t::array_end) && depth == kItemDepth + 1 &&
               item_key == "result") {
      span.to = position();
      span_closed = true;
    } else if (event == event_t::object_end && depth == kItemDepth) {
      item_key.clear();
      if (!parsed.is_object()) return true;
      const auto it = parsed.find("result");
      if (it == parsed.end()) return true;
      const std::size_t k = spans->size();
      if (span_closed)
        spans->push_back(span);
      else {
        spans->push_back({});
        (*kept)[k] = dump(*it, -1);
      }
      *it = k;
      span_closed = false;
    }
    return true;
  };
  try {
    part.manifest = nlohmann::json::parse(in, set_aside);
  } catch (const std::exception& e) {
    throw InputError(about(plain_text(manifest_path.string()), std::string("not valid JSON: ") + e.what()));
  }
  part.results = spans->size();
  part.result_text = [manifest_path, spans, kept](std::size_t k) {
    if (k >= spans->size())
      throw InputError(about(plain_text(manifest_path.string()), "holds no result " + std::to_string(k)));
    const auto text = kept->find(k);
    return text != kept->end() ? text->second : read_span(manifest_path, (*spans)[k]);
  };
  part.read_file = [folder, name](const std::string& relative) {
    try {
      return read_file_bytes(folder / relative);
    } catch (const InputError&) {
      throw InputError(about(plain_text(name), "its file " + plain_text(relative) + " is missing"));
    }
  };
  return part;
}

namespace {

constexpr const char* kBundleHeader = "pushpred-bundle 1\n";

/// A bundle's header and name, with room reserved for `data_bytes` more.
std::string bundle_head(const std::string& name, std::size_t data_bytes) {
  const std::string lengths = std::to_string(name.size()) + " " + std::to_string(data_bytes) + "\n";
  std::string bundle;
  bundle.reserve(std::strlen(kBundleHeader) + lengths.size() + name.size() + data_bytes);
  bundle += kBundleHeader;
  bundle += lengths;
  bundle += name;
  return bundle;
}

}  // namespace

std::string file_bundle(const std::string& name, const std::string& data) {
  std::string bundle = bundle_head(name, data.size());
  bundle += data;
  return bundle;
}

std::string file_bundle_of(const std::string& name, const fs::path& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  const std::streamoff size = in ? static_cast<std::streamoff>(in.tellg()) : -1;
  if (size < 0) throw InputError(about(plain_text(path.string()), "cannot be read"));
  std::string bundle = bundle_head(name, static_cast<std::size_t>(size));
  const std::size_t at = bundle.size();
  bundle.resize(at + static_cast<std::size_t>(size));
  if (!in.seekg(0) || !in.read(bundle.data() + at, size))
    throw InputError(about(plain_text(path.string()), "cannot be read"));
  return bundle;
}

std::string unpack_file_bundle(const std::string& name, const std::string& bundle, const fs::path& folder) {
  const auto unreadable = [&](const std::string& why) {
    return InputError(about(plain_text(name), "its partial output is not readable: " + why));
  };
  const std::string header = kBundleHeader;
  if (bundle.compare(0, header.size(), header) != 0) throw unreadable("not a partial bundle");
  // A length: decimal digits, at most 15 (a petabyte), ended by `end`.
  std::size_t at = header.size();
  const auto length = [&](char end) {
    std::size_t value = 0, digits = 0;
    while (at < bundle.size() && bundle[at] >= '0' && bundle[at] <= '9' && digits < 15) {
      value = value * 10 + static_cast<std::size_t>(bundle[at++] - '0');
      ++digits;
    }
    if (digits == 0 || at >= bundle.size() || bundle[at] != end) throw unreadable("a garbled length line");
    ++at;
    return value;
  };
  const std::size_t name_bytes = length(' ');
  const std::size_t data_bytes = length('\n');
  if (name_bytes > bundle.size() - at || data_bytes > bundle.size() - at - name_bytes)
    throw unreadable("it ends inside its file");
  if (data_bytes < bundle.size() - at - name_bytes) throw unreadable("bytes after its file");
  const std::string relative = bundle.substr(at, name_bytes);
  if (!relative_inside(relative))
    throw InputError(
        about(plain_text(name), "its file '" + plain_text(relative) + "' is not a path inside the output"));
  write_under(folder, relative, bundle.data() + at + name_bytes, data_bytes);
  return relative;
}

nlohmann::json MergedItem::result() const {
  if (!result_at || !part) throw InputError("it lists no result");
  return nlohmann::json::parse(part->result_text(*result_at));
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
      const int index = json_whole_number<int>(m.at("shard").at("index"), "its shard index");
      const int n = json_whole_number<int>(m.at("shard").at("count"), "its shard count");
      const std::size_t inputs = json_whole_number<std::size_t>(m.at("inputs").at("count"), "its input count");
      const std::string print = m.at("inputs").at("fingerprint").get<std::string>();
      const std::string version = m.at("pushpred_version").get<std::string>();
      if (n < 1 || index < 1 || index > n)
        throw InputError("its shard " + std::to_string(index) + "/" + std::to_string(n) + " is not a share I/N");
      // Each of the n shards holds its share of the inputs, so a part's item list bounds how many there can be.
      const std::size_t listed = m.at("items").size();
      if (inputs / static_cast<std::size_t>(n) > listed + 1)
        throw InputError("it claims " + std::to_string(inputs) + " inputs, more than " + std::to_string(n) +
                         " shards of its " + std::to_string(listed) + " items hold");
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
        mi.index = json_whole_number<std::size_t>(entry.at("index"), "its item index");
        if (mi.index >= count)
          throw InputError("its item " + std::to_string(mi.index) + " is beyond the " + std::to_string(count) +
                           " inputs");
        if (entry.contains("result")) {
          // Its position among the part's result texts (partial_output, read_partial_output).
          const std::size_t at = json_whole_number<std::size_t>(entry.at("result"), "its result position");
          if (at >= part.results) throw InputError("its result " + std::to_string(at) + " is not held");
          mi.result_at = at;
          mi.files = entry.at("files").get<std::vector<std::string>>();
          for (const auto& f : mi.files) require_relative_inside(f);
        } else {
          const auto& f = entry.at("failure");
          mi.failure = BatchFailure{f.at("source").get<std::string>(), f.at("reason").get<std::string>(),
                                    f.value("skipped", false)};
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
