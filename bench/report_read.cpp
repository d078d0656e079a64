#include "bench/report_read.h"
#include "bench/results_doc.h"
#include "masq/error.h"
#include "masq/masq.h"
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <sstream>

namespace masq {

namespace {
using nlohmann::json;

// One file's fields, each checked: a failure names the file and the field's JSON pointer.
struct Checked {
  std::string file;

  [[noreturn]] void fail(const std::string& pointer, const std::string& why) const {
    throw Error(file + ": " + pointer + ": " + why);
  }
  const json& field(const json& parent, const std::string& pointer, const std::string& key, json::value_t type) const {
    auto it = parent.find(key);
    std::string at = pointer + "/" + key;
    if (it == parent.end()) fail(at, "missing");
    if (!has_type(*it, type)) fail(at, std::string("not ") + type_name(type) + " (" + it->type_name() + ")");
    return *it;
  }
  std::string string(const json& parent, const std::string& pointer, const std::string& key) const {
    return field(parent, pointer, key, json::value_t::string).get<std::string>();
  }
  // A string that older or hand-written files may lack: "" then.
  std::string optional_string(const json& parent, const std::string& pointer, const std::string& key) const {
    return parent.contains(key) ? string(parent, pointer, key) : std::string();
  }
  // number_unsigned stands for any integer here.
  static bool has_type(const json& j, json::value_t type) {
    return type == json::value_t::number_unsigned ? j.is_number_integer() : j.type() == type;
  }
  static const char* type_name(json::value_t type) {
    switch (type) {
      case json::value_t::object: return "an object";
      case json::value_t::array: return "an array";
      case json::value_t::string: return "a string";
      case json::value_t::boolean: return "true or false";
      default: return "an integer";
    }
  }
};

json parse_file(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(file + ": cannot read it (" + (std::filesystem::exists(file) ? "permission?" : "no such file") + ")");
  std::ostringstream text;
  text << in.rdbuf();
  try {
    return json::parse(text.str());
  } catch (const json::parse_error& e) {
    std::string why = e.what();
    if (auto close = why.find("] "); why.rfind("[json.exception", 0) == 0 && close != std::string::npos)
      why = why.substr(close + 2);
    throw Error(fmt::format("{}: not JSON (byte {}: {})", file, e.byte, why));
  }
}

// The command that writes this file's suites again with this masq.
std::string rerun_command(const json& doc) {
  if (doc.contains("run") && doc["run"].is_object() && doc["run"].value("command", json()).is_string())
    return doc["run"]["command"].get<std::string>();
  std::string cmd = "masq bench";
  if (doc.contains("suites") && doc["suites"].is_object())
    for (auto& [name, suite] : doc["suites"].items()) cmd += " --suite " + name;
  return cmd;
}

// Refuses anything but a results file of the version this masq reads.
void check_format(const Checked& c, const json& doc) {
  if (!doc.is_object()) c.fail("", "not a masq results file (a JSON " + std::string(doc.type_name()) + ", not an object)");
  const bool before_versions = !doc.contains("format") && doc.contains("machine") && doc.contains("suites");
  if (before_versions)
    throw Error(fmt::format("{}: a masq results file of format version 1 (written before masq {} added the format "
                            "version and the tables); masq report reads version {}: rerun `{}` with this masq",
                            c.file, api::version(), results_format_version, rerun_command(doc)));
  if (!doc.contains("format") || doc["format"] != results_format)
    throw Error(fmt::format("{}: not a masq results file (no \"format\": \"{}\"; masq bench --suite writes one as "
                            "OUT/results.json)",
                            c.file, results_format));
  const json& version = c.field(doc, "", "format_version", json::value_t::number_unsigned);
  if (version.get<long long>() != results_format_version) {
    std::string writer = doc.value("masq_version", json()).is_string() ? doc["masq_version"].get<std::string>() : "?";
    throw Error(fmt::format("{}: a masq results file of format version {} (written by masq {}); masq report {} reads "
                            "version {}: rerun `{}` with this masq",
                            c.file, version.dump(), writer, api::version(), results_format_version,
                            rerun_command(doc)));
  }
}

std::string parent_folder_name(const std::string& file) {
  std::filesystem::path dir = std::filesystem::absolute(file).lexically_normal().parent_path();
  std::string name = dir.filename().string();
  return name.empty() ? file : name;
}
} // namespace

ReportRun read_results_file(const std::string& file, const std::string& label) {
  Checked c{file};
  json doc = parse_file(file);
  check_format(c, doc);
  ReportRun run;
  run.file = file;
  run.label = label.empty() ? parent_folder_name(file) : label;
  run.masq_version = c.string(doc, "", "masq_version");
  run.machine = c.field(doc, "", "machine", json::value_t::object);
  const json& backends = c.field(run.machine, "/machine", "backends", json::value_t::object);
  for (auto& [name, device] : backends.items()) run.backends[name] = c.string(backends, "/machine/backends", name);
  for (const char* key : {"cpu", "memory", "os", "kernel", "compiler", "date", "git_commit", "embree"})
    c.optional_string(run.machine, "/machine", key);
  const json& how = c.field(doc, "", "run", json::value_t::object);
  run.command = c.string(how, "/run", "command");
  run.quick = c.field(how, "/run", "quick", json::value_t::boolean).get<bool>();
  const json& suites = c.field(doc, "", "suites", json::value_t::object);
  for (auto& [name, suite] : suites.items()) {
    std::string at = "/suites/" + name;
    if (!suite.is_object()) c.fail(at, "not an object");
    ReportSuite s{name, c.string(suite, at, "title"), c.optional_string(suite, at, "method"), {}};
    const json& tables = c.field(suite, at, "tables", json::value_t::array);
    for (std::size_t i = 0; i < tables.size(); ++i) {
      std::string table_at = at + "/tables/" + std::to_string(i);
      try {
        s.tables.push_back(tables[i].get<Table>());
      } catch (const Error& e) { // from_json: the pointer inside the table, then why
        throw Error(file + ": " + table_at + e.what());
      }
    }
    run.suites.push_back(std::move(s));
  }
  return run;
}

std::vector<ReportRun> read_results_files(const std::vector<std::string>& files,
                                          const std::map<std::string, std::string>& labels) {
  if (files.empty()) throw Error("report: no results files given (masq report RUN/results.json ...)");
  namespace fs = std::filesystem;
  auto same = [](const std::string& a, const std::string& b) {
    std::error_code ec;
    return a == b || fs::equivalent(a, b, ec);
  };
  for (auto& [file, name] : labels) {
    bool found = false;
    for (const std::string& f : files) found = found || same(f, file);
    if (!found) throw Error("report: --label " + file + "=" + name + " names no file given");
  }
  std::vector<ReportRun> runs;
  for (std::size_t i = 0; i < files.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j)
      if (same(files[i], files[j])) {
        std::string also = files[i] == files[j] ? "" : " (as " + files[j] + ")";
        throw Error(files[i] + ": given twice" + also + "; each run once");
      }
    std::string label;
    for (auto& [file, name] : labels)
      if (same(files[i], file)) label = name;
    runs.push_back(read_results_file(files[i], label));
  }
  // Two runs of one label ("results" twice) get " 2", " 3", ... in order.
  std::map<std::string, int> seen;
  for (ReportRun& r : runs) {
    int n = ++seen[r.label];
    // Appends rather than " " + s: GCC 12 reports a false -Wstringop-overflow on that operator+.
    if (n > 1) r.label.append(" ").append(std::to_string(n));
  }
  return runs;
}

} // namespace masq
