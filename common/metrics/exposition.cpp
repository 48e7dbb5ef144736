// ParseExposition: a line-by-line reader of the text format.
#include "metrics/exposition.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>
#include <set>

namespace fleetloc::metrics {

namespace {

bool NameStart(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' || c == ':';
}
bool NameChar(char c) { return NameStart(c) || (c >= '0' && c <= '9'); }

// A metric name (`colons` true) or label name at the start of `s`; its length (0: none).
size_t NameLength(std::string_view s, bool colons) {
  size_t n = 0;
  while (n < s.size() && NameChar(s[n]) && (colons || s[n] != ':')) ++n;
  if (n > 0 && !NameStart(s[0])) return 0;
  return n;
}

// A float as Prometheus reads it (Go's ParseFloat: NaN and Inf in any letter case).
bool ParseValue(std::string_view text, double* out) {
  std::string lower(text);
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (lower == "+inf" || lower == "inf") {
    *out = std::numeric_limits<double>::infinity();
    return true;
  }
  if (lower == "-inf") {
    *out = -std::numeric_limits<double>::infinity();
    return true;
  }
  if (lower == "nan") {
    *out = std::numeric_limits<double>::quiet_NaN();
    return true;
  }
  if (text.empty()) return false;
  auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), *out);
  return ec == std::errc() && ptr == text.data() + text.size();
}

// The family a sample name belongs to, given the declared types (histogram/summary suffixes).
std::string FamilyOf(const std::string& name, const std::map<std::string, std::string>& types) {
  if (types.contains(name)) return name;
  for (const char* suffix : {"_bucket", "_sum", "_count"}) {
    const std::string_view sv(suffix);
    if (name.size() > sv.size() && name.ends_with(sv)) {
      std::string base = name.substr(0, name.size() - sv.size());
      auto it = types.find(base);
      if (it != types.end() &&
          (it->second == "histogram" || (it->second == "summary" && sv != "_bucket")))
        return base;
    }
  }
  return "";
}

// Reads label `key`'s value after its opening quote, unescaping \n, \\ and \"; advances `r` past
// the closing quote. False with `error` set on a bad escape or a missing closing quote.
bool ReadLabelValue(std::string_view* r, const std::string& key, std::string* value,
                    std::string* error) {
  while (!r->empty()) {
    const char c = (*r)[0];
    r->remove_prefix(1);
    if (c == '"') return true;
    if (c != '\\') {
      *value += c;
      continue;
    }
    if (r->empty()) break;
    const char e = (*r)[0];
    r->remove_prefix(1);
    if (e == 'n') {
      *value += '\n';
    } else if (e == '\\' || e == '"') {
      *value += e;
    } else {
      *error = "label " + key + ": bad escape";
      return false;
    }
  }
  *error = "label " + key + ": unterminated value";
  return false;
}

// Parses `{a="b",c="d"}` at the start of `s`; advances `s` past it.
bool ParseLabels(std::string_view* s, std::map<std::string, std::string>* labels,
                 std::string* error) {
  std::string_view r = *s;
  r.remove_prefix(1);  // '{'
  while (!r.empty() && r[0] != '}') {
    const size_t n = NameLength(r, false);
    if (n == 0) {
      *error = "bad label name";
      return false;
    }
    const std::string key(r.substr(0, n));
    r.remove_prefix(n);
    if (r.size() < 2 || r[0] != '=' || r[1] != '"') {
      *error = "label " + key + ": expected =\"";
      return false;
    }
    r.remove_prefix(2);
    std::string value;
    if (!ReadLabelValue(&r, key, &value, error)) return false;
    if (!labels->emplace(key, value).second) {
      *error = "label " + key + " twice";
      return false;
    }
    if (!r.empty() && r[0] == ',') {
      r.remove_prefix(1);
    } else if (r.empty() || r[0] != '}') {
      *error = "expected , or } after label " + key;
      return false;
    }
  }
  if (r.empty()) {
    *error = "unterminated label set";
    return false;
  }
  r.remove_prefix(1);
  *s = r;
  return true;
}

// Checks every histogram's series: le labels ascending, counts cumulative, +Inf == _count.
Status CheckHistograms(const Exposition& e) {
  for (const auto& [family, type] : e.types) {
    if (type != "histogram") continue;
    // Series by their labels without le.
    std::map<std::map<std::string, std::string>, std::vector<std::pair<double, double>>> buckets;
    std::map<std::map<std::string, std::string>, double> counts;
    for (const Sample& s : e.samples) {
      std::map<std::string, std::string> key = s.labels;
      if (s.name == family + "_bucket") {
        auto le = key.find("le");
        double bound = 0;
        if (le == key.end() || !ParseValue(le->second, &bound))
          return InvalidInput(family + ": bucket without a numeric le");
        key.erase("le");
        buckets[key].push_back({bound, s.value});
      } else if (s.name == family + "_count") {
        counts[key] = s.value;
      }
    }
    for (const auto& [series, list] : buckets) {
      for (size_t i = 1; i < list.size(); ++i) {
        if (!(list[i].first > list[i - 1].first))
          return InvalidInput(family + ": le not ascending");
        if (list[i].second < list[i - 1].second)
          return InvalidInput(family + ": bucket counts not cumulative");
      }
      if (list.empty() || !std::isinf(list.back().first))
        return InvalidInput(family + ": no +Inf bucket");
      auto count = counts.find(series);
      if (count == counts.end() || count->second != list.back().second) {
        return InvalidInput(family + ": +Inf bucket differs from _count");
      }
    }
  }
  return Status::Ok();
}

}  // namespace

Result<double> Exposition::Value(const std::string& name,
                                 const std::map<std::string, std::string>& labels) const {
  for (const Sample& s : samples) {
    if (s.name != name) continue;
    bool all = true;
    for (const auto& [k, v] : labels) {
      auto it = s.labels.find(k);
      all = all && it != s.labels.end() && it->second == v;
    }
    if (all) return s.value;
  }
  return NotFound("no sample " + name);
}

namespace {

// A "# HELP" or "# TYPE" line (other comments are skipped) into `e`; what is wrong with it, or "".
std::string ParseMetadataLine(std::string_view line, Exposition* e,
                              std::set<std::string>* help_seen) {
  const bool help = line.starts_with("# HELP "), type = line.starts_with("# TYPE ");
  if (!help && !type) return "";  // a comment
  std::string_view rest = line.substr(7);
  const size_t n = NameLength(rest, true);
  if (n == 0 || (n < rest.size() && rest[n] != ' ')) return "bad metric name in HELP/TYPE";
  const std::string name(rest.substr(0, n));
  const std::string_view arg = n < rest.size() ? rest.substr(n + 1) : std::string_view();
  if (help) {
    if (!help_seen->insert(name).second) return "second HELP for " + name;
    return "";
  }
  static const std::set<std::string_view> kTypes = {"counter", "gauge", "histogram", "summary",
                                                    "untyped"};
  if (!kTypes.contains(arg)) return "unknown type '" + std::string(arg) + "'";
  for (const Sample& s : e->samples) {
    if (s.name == name || s.name.starts_with(name + "_")) {
      if (FamilyOf(s.name, {{name, std::string(arg)}}) == name)
        return "TYPE of " + name + " after its samples";
    }
  }
  if (!e->types.emplace(name, std::string(arg)).second) return "second TYPE for " + name;
  return "";
}

// A sample line appended to `e`; what is wrong with it, or "".
std::string ParseSampleLine(std::string_view line, Exposition* e) {
  Sample s;
  const size_t n = NameLength(line, true);
  if (n == 0) return "expected a metric name";
  s.name = std::string(line.substr(0, n));
  line.remove_prefix(n);
  if (!line.empty() && line[0] == '{') {
    std::string error;
    if (!ParseLabels(&line, &s.labels, &error)) return error;
  }
  if (line.empty() || line[0] != ' ') return "expected a space before the value";
  line.remove_prefix(1);
  const size_t space = line.find(' ');
  if (!ParseValue(line.substr(0, space), &s.value))
    return "bad value '" + std::string(line.substr(0, space)) + "'";
  if (space != std::string_view::npos) {
    long long timestamp = 0;
    const std::string_view ts = line.substr(space + 1);
    auto [ptr, ec] = std::from_chars(ts.data(), ts.data() + ts.size(), timestamp);
    if (ec != std::errc() || ptr != ts.data() + ts.size()) return "bad timestamp";
  }
  const std::string family = FamilyOf(s.name, e->types);
  if (family.empty()) return "sample " + s.name + " before its TYPE line";
  const std::string& type = e->types[family];
  if (type == "counter" && s.value < 0) return "negative counter " + s.name;
  e->samples.push_back(std::move(s));
  return "";
}

}  // namespace

Result<Exposition> ParseExposition(std::string_view text) {
  Exposition e;
  std::set<std::string> help_seen;
  int line_no = 0;
  while (!text.empty()) {
    const size_t end = text.find('\n');
    if (end == std::string_view::npos) return InvalidInput("the last line has no newline");
    std::string_view line = text.substr(0, end);
    text.remove_prefix(end + 1);
    ++line_no;
    if (line.empty()) continue;
    const std::string error =
        line[0] == '#' ? ParseMetadataLine(line, &e, &help_seen) : ParseSampleLine(line, &e);
    if (!error.empty()) return InvalidInput("line " + std::to_string(line_no) + ": " + error);
  }
  if (Status shape = CheckHistograms(e); !shape.ok()) return shape;
  return e;
}

}  // namespace fleetloc::metrics
