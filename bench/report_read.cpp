#include "bench/report_read.h"
#include "bench/json_field.h"
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
void check_format(const std::string& file, const json& doc) {
  if (!doc.is_object())
    throw Error(file + ": not a masq results file (a JSON " + std::string(doc.type_name()) + ", not an object)");
  const bool before_versions = !doc.contains("format") && doc.contains("machine") && doc.contains("suites");
  if (before_versions)
    throw Error(fmt::format("{}: a masq results file of format version 1 (written before masq {} added the format "
                            "version and the tables); masq report reads version {}: rerun `{}` with this masq",
                            file, api::version(), results_format_version, rerun_command(doc)));
  if (!doc.contains("format") || doc["format"] != results_format)
    throw Error(fmt::format("{}: not a masq results file (no \"format\": \"{}\"; masq bench --suite writes one as "
                            "OUT/results.json)",
                            file, results_format));
  const json& version = json_field(doc, "", "format_version", json::value_t::number_unsigned);
  if (version.get<long long>() != results_format_version) {
    std::string writer = doc.value("masq_version", json()).is_string() ? doc["masq_version"].get<std::string>() : "?";
    throw Error(fmt::format("{}: a masq results file of format version {} (written by masq {}); masq report {} reads "
                            "version {}: rerun `{}` with this masq",
                            file, version.dump(), writer, api::version(), results_format_version,
                            rerun_command(doc)));
  }
}

std::string parent_folder_name(const std::string& file) {
  std::filesystem::path dir = std::filesystem::absolute(file).lexically_normal().parent_path();
  std::string name = dir.filename().string();
  return name.empty() ? file : name;
}


// The fields of a checked results file; json_field's errors name the field, the caller
// adds the file.
ReportRun read_fields(const json& doc) {
  ReportRun run;
  run.masq_version = json_string(doc, "", "masq_version");
  run.machine = json_field(doc, "", "machine", json::value_t::object);
  const json& backends = json_field(run.machine, "/machine", "backends", json::value_t::object);
  for (auto& [name, device] : backends.items()) run.backends[name] = json_string(backends, "/machine/backends", name);
  for (const char* key : {"cpu", "memory", "os", "kernel", "compiler", "date", "git_commit", "embree"})
    if (run.machine.contains(key)) json_string(run.machine, "/machine", key); // optional, but text where present
  const json& how = json_field(doc, "", "run", json::value_t::object);
  run.command = json_string(how, "/run", "command");
  run.quick = json_field(how, "/run", "quick", json::value_t::boolean).get<bool>();
  const json& suites = json_field(doc, "", "suites", json::value_t::object);
  for (auto& [name, suite] : suites.items()) {
    std::string at = "/suites/" + name;
    if (!suite.is_object()) throw Error(at + ": not an object");
    ReportSuite s{name, json_string(suite, at, "title"),
                  suite.contains("method") ? json_string(suite, at, "method") : std::string(), {}};
    const json& tables = json_field(suite, at, "tables", json::value_t::array);
    for (std::size_t i = 0; i < tables.size(); ++i) {
      try {
        s.tables.push_back(tables[i].get<Table>());
      } catch (const Error& e) { // from_json: the pointer inside the table, then why
        throw Error(at + "/tables/" + std::to_string(i) + e.what());
      }
    }
    run.suites.push_back(std::move(s));
  }
  return run;
}
} // namespace

ReportRun read_results_file(const std::string& file, const std::string& label) {
  json doc = parse_file(file);
  ReportRun run;
  try {
    check_format(file, doc);
    run = read_fields(doc);
  } catch (const Error& e) {
    const std::string why = e.what();
    throw why.rfind(file + ": ", 0) == 0 ? e : Error(file + ": " + why);
  }
  run.file = file;
  run.label = label.empty() ? parent_folder_name(file) : label;
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
