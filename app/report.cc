#include "app/report.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <initializer_list>

#include "app/csv_writer.h"

namespace momenta {

void JsonString(const std::string& text, std::string* out) {
  *out += '"';
  for (const char ch : text) {
    const unsigned char c = ch;
    switch (c) {
      case '"':
        *out += "\\\"";
        break;
      case '\\':
        *out += "\\\\";
        break;
      case '\n':
        *out += "\\n";
        break;
      case '\r':
        *out += "\\r";
        break;
      case '\t':
        *out += "\\t";
        break;
      case '<':
        *out += "\\u003c";
        break;
      default:
        if (c < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          *out += buf;
        } else {
          *out += static_cast<char>(c);
        }
    }
  }
  *out += '"';
}

namespace {

#include "report_assets.inc"

std::string Join(const char* const* pieces) {
  std::string s;
  for (; *pieces; ++pieces) s += *pieces;
  return s;
}

/// A number with 9 significant digits (the page's plots and scene need no more; it keeps the
/// page small); NaN and infinities, which JSON lacks, are null.
void JsonNumber(double v, std::string* out) {
  if (!std::isfinite(v)) {
    *out += "null";
    return;
  }
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  *out += buf;
}

void JsonStrings(const std::vector<std::string>& list, std::string* out) {
  *out += '[';
  for (size_t k = 0; k < list.size(); ++k) {
    if (k) *out += ',';
    JsonString(list[k], out);
  }
  *out += ']';
}

void JsonTable(const ReportTable& table, std::string* out) {
  *out += '[';
  for (size_t k = 0; k < table.size(); ++k) {
    *out += k ? ",[" : "[";
    JsonString(table[k].first, out);
    *out += ',';
    JsonString(table[k].second, out);
    *out += ']';
  }
  *out += ']';
}

/// The rows the page shows: all of them up to kMaxReportRows, else every k-th, the rows of
/// events (both limits) and the last.
std::vector<size_t> ShownRows(const std::vector<double>& time) {
  const size_t n = time.size();
  const size_t stride = n <= kMaxReportRows ? 1 : (n + kMaxReportRows - 1) / kMaxReportRows;
  std::vector<size_t> rows;
  for (size_t i = 0; i < n; ++i) {
    const bool event = (i > 0 && time[i] == time[i - 1]) || (i + 1 < n && time[i] == time[i + 1]);
    if (i % stride == 0 || event || i + 1 == n) rows.push_back(i);
  }
  return rows;
}

/// `"key":"value"` for each pair, comma-separated (the caller writes the braces around them).
void JsonStringFields(std::initializer_list<std::pair<const char*, const std::string*>> fields,
                      std::string* out) {
  bool first = true;
  for (const auto& [key, value] : fields) {
    *out += first ? "\"" : ",\"";
    *out += key;
    *out += "\":";
    JsonString(*value, out);
    first = false;
  }
}

/// The shapes the page draws: those whose `if` (docs/FORMAT.md "Animation") holds at the first
/// row, or that have none.
std::vector<const SceneShape*> DrawnShapes(const ReportData& d) {
  std::vector<const SceneShape*> out;
  for (const SceneShape& shape : d.scene.shapes) {
    bool drawn = true;
    for (const SceneField& f : shape.fields) {
      if (f.key != "if" || f.columns.size() != 1 || d.time.empty()) continue;
      for (size_t c = 0; c < d.columns.size() && c < d.values.size(); ++c) {
        if (d.columns[c] == f.columns[0] && !d.values[c].empty()) drawn = d.values[c][0] != 0;
      }
    }
    if (drawn) out.push_back(&shape);
  }
  return out;
}

/// The page's data as one JSON object (report/report.js reads it).
std::string DataJson(const ReportData& d) {
  std::string j = "{";
  JsonStringFields({{"model", &d.model_name},
                    {"file", &d.model_file},
                    {"result", &d.result_file},
                    {"doc", &d.doc}},
                   &j);
  j += ",\"notes\":";
  JsonStrings(d.notes, &j);
  j += ",\"parameters\":[";
  for (size_t k = 0; k < d.parameters.size(); ++k) {
    const ReportParameter& p = d.parameters[k];
    j += k ? ",{" : "{";
    JsonStringFields({{"name", &p.name}, {"unit", &p.unit}, {"doc", &p.doc}}, &j);
    j += ",\"value\":";
    JsonNumber(p.value, &j);
    j += '}';
  }
  j += "],\"build\":";
  JsonTable(d.build, &j);
  j += ",\"solver\":";
  JsonTable(d.solver, &j);
  j += ",\"columns\":";
  JsonStrings(d.columns, &j);
  j += ",\"units\":";
  std::vector<std::string> units = d.units;
  units.resize(d.columns.size());
  JsonStrings(units, &j);
  j += ",\"plotted\":" + std::to_string(d.num_plotted);
  j += ",\"events\":[";
  const std::vector<double> events = d.EventTimes();
  for (size_t k = 0; k < events.size(); ++k) {
    if (k) j += ',';
    JsonNumber(events[k], &j);
  }
  // Columns of numbers, the time first.
  const std::vector<size_t> rows = ShownRows(d.time);
  j += "],\"rows\":" + std::to_string(d.time.size()) + ",\"data\":[";
  for (size_t c = 0; c <= d.values.size(); ++c) {
    const std::vector<double>& col = c == 0 ? d.time : d.values[c - 1];
    j += c ? ",[" : "[";
    for (size_t k = 0; k < rows.size(); ++k) {
      if (k) j += ',';
      JsonNumber(col[rows[k]], &j);
    }
    j += ']';
  }
  j += "],\"space\":";
  j += d.scene.space ? "true" : "false";
  j += ",\"scene\":[";
  const std::vector<const SceneShape*> drawn = DrawnShapes(d);
  for (size_t s = 0; s < drawn.size(); ++s) {
    const SceneShape& shape = *drawn[s];
    j += s ? ",{\"kind\":" : "{\"kind\":";
    JsonString(shape.kind, &j);
    j += ",\"owner\":";
    JsonString(shape.owner, &j);
    j += ",\"fields\":{";
    bool first = true;
    for (const SceneField& f : shape.fields) {
      if (f.key == "if") continue;
      j += first ? "" : ",";
      first = false;
      JsonString(f.key, &j);
      j += ':';
      JsonStrings(f.columns, &j);
    }
    j += "}}";
  }
  j += "]}";
  return j;
}

/// Replaces the first `token` at or after `*from` by `value` and moves `*from` past it, so that
/// text filled in earlier (a model's doc) is never taken for a later placeholder.
void Fill(std::string* text, const std::string& token, const std::string& value, size_t* from) {
  const size_t at = text->find(token, *from);
  if (at == std::string::npos) return;
  text->replace(at, token.size(), value);
  *from = at + value.size();
}

}  // namespace

void ReportData::Row(double t, const std::vector<double>& v) {
  if (values.size() < v.size()) values.resize(v.size());
  time.push_back(t);
  for (size_t k = 0; k < v.size(); ++k) values[k].push_back(v[k]);
}

std::vector<double> ReportData::EventTimes() const {
  std::vector<double> out;
  for (size_t i = 1; i < time.size(); ++i) {
    if (time[i] == time[i - 1] && (out.empty() || out.back() != time[i])) out.push_back(time[i]);
  }
  return out;
}

bool ReportHasPlots() { return MOMENTA_HAVE_UPLOT != 0; }

bool ReportHasThree() { return MOMENTA_HAVE_THREE != 0; }

std::string ReportHtml(const ReportData& data) {
  std::string html = Join(kReportHtml);
  // The placeholders in the order report/report.html has them.
  size_t from = 0;
  Fill(&html, "/*@REPORT_CSS@*/", Join(kReportCss), &from);
  Fill(&html, "/*@UPLOT_CSS@*/", Join(kUplotCss), &from);
  Fill(&html, "/*@DATA@*/", DataJson(data), &from);
  Fill(&html, "/*@UPLOT_JS@*/", Join(kUplotJs), &from);
  // three.js and the 3-D scene's script only in a page that draws a 3-D scene (700 KB).
  const bool space = data.scene.space && !DrawnShapes(data).empty();
  Fill(&html, "/*@THREE_JS@*/", space ? Join(kThreeJs) + "\n" + Join(kScene3dJs) : "", &from);
  Fill(&html, "/*@REPORT_JS@*/", Join(kReportJs), &from);
  return html;
}

void WriteReport(const std::string& path, const std::string& html) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw CsvWriteError("cannot write the report " + path + ": " + std::strerror(errno));
  out.write(html.data(), static_cast<std::streamsize>(html.size()));
  out.flush();
  if (!out) throw CsvWriteError("cannot write the report " + path + ": " + std::strerror(errno));
}

}  // namespace momenta
