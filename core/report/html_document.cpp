#include "report/html_document.hpp"

#include <nettle/base64.h>

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <stdexcept>

namespace fibrodem {

namespace {

// Plain, readable at full width, printable; no web fonts (offline).
constexpr const char* kStyle = R"(
body{font-family:sans-serif;margin:0 auto;max-width:1400px;padding:0 1.5em 3em;color:#222;line-height:1.4}
h1{border-bottom:2px solid #1f77b4;padding-bottom:.2em}
h2{margin-top:1.6em;border-bottom:1px solid #ccc}
table{border-collapse:collapse;margin:.5em 0;font-size:.92em}
th,td{border:1px solid #ccc;padding:.2em .6em}
th{background:#f0f4f8;text-align:left}
td.num{text-align:right;font-variant-numeric:tabular-nums}
dl{display:grid;grid-template-columns:max-content auto;gap:.15em 1em}
dt{font-weight:bold}
dd{margin:0}
figure{margin:1em 0}
figcaption{font-weight:bold;margin-bottom:.3em}
figure img{max-width:100%;height:auto;border:1px solid #ddd}
.row{display:flex;flex-wrap:wrap;gap:1.5em}
.row>figure{flex:1 1 400px}
.notice{padding:.6em 1em;margin:1em 0;border-left:6px solid}
.notice.error{background:#fde8e8;border-color:#d62728}
.notice.warning{background:#fff4e0;border-color:#ff7f0e}
.notice.info{background:#eef4fb;border-color:#1f77b4}
.notice.ok{background:#e8f5e8;border-color:#2ca02c}
pre{background:#f7f7f7;padding:.6em;overflow:auto;max-height:40em;font-size:.85em}
input[type=range]{width:100%}
)";

// One function for every snapshot slider: shows frame k of slider `id`;
// another plays the frames in a loop (about 7 per second) or pauses them.
constexpr const char* kSliderScript = R"(
function fibrodemShowFrame(id,k){
  var frames=document.querySelectorAll('#'+id+' img');
  for(var i=0;i<frames.length;++i)frames[i].style.display=(i==k)?'':'none';
  document.getElementById(id+'-label').textContent=frames[k].alt;
  document.getElementById(id+'-range').value=k;
}
var fibrodemTimers={};
function fibrodemPlay(id,button){
  if(fibrodemTimers[id]){clearInterval(fibrodemTimers[id]);delete fibrodemTimers[id];button.textContent='play';return;}
  var range=document.getElementById(id+'-range');
  button.textContent='pause';
  fibrodemTimers[id]=setInterval(function(){fibrodemShowFrame(id,(+range.value+1)%(+range.max+1));},150);
}
)";

bool is_number(const std::string& s) {
  if (s.empty()) return false;
  char* end = nullptr;
  std::strtod(s.c_str(), &end);
  return end != nullptr && *end == '\0';
}

}  // namespace

std::string html_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

// Base64 as RFC 4648 section 4 (with '=' padding), by GNU Nettle (also
// the project's SHA-256: util/sha256.cpp).
std::string base64(const std::string& bytes) {
  std::string out(BASE64_ENCODE_RAW_LENGTH(bytes.size()), '\0');
  base64_encode_raw(out.data(), bytes.size(), reinterpret_cast<const std::uint8_t*>(bytes.data()));
  return out;
}

// The whole file in one read (a tissue run's snapshots are megabytes).
std::optional<std::string> read_file_bytes(const std::filesystem::path& file) {
  std::error_code error;
  const auto size = std::filesystem::file_size(file, error);
  std::ifstream in(file, std::ios::binary);
  if (error || !in) return std::nullopt;
  std::string bytes(size, '\0');
  if (!in.read(bytes.data(), static_cast<std::streamsize>(size))) return std::nullopt;
  return bytes;
}

HtmlDocument::HtmlDocument(std::string title) : title_(std::move(title)) {}

void HtmlDocument::heading(int level, const std::string& text, const std::string& id) {
  body_ << "<h" << level;
  if (!id.empty()) body_ << " id=\"" << html_escape(id) << "\"";
  body_ << ">" << html_escape(text) << "</h" << level << ">\n";
}

void HtmlDocument::paragraph(const std::string& text) { body_ << "<p>" << html_escape(text) << "</p>\n"; }

void HtmlDocument::notice(const std::string& kind, const std::string& title, const std::vector<std::string>& lines) {
  body_ << "<div class=\"notice " << html_escape(kind) << "\"><strong>" << html_escape(title) << "</strong>";
  if (!lines.empty()) {
    body_ << "<ul>";
    for (const auto& line : lines) body_ << "<li>" << html_escape(line) << "</li>";
    body_ << "</ul>";
  }
  body_ << "</div>\n";
}

void HtmlDocument::table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows) {
  std::vector<bool> numeric(header.size(), !rows.empty());
  for (const auto& row : rows)
    for (std::size_t c = 0; c < row.size() && c < numeric.size(); ++c)
      if (!row[c].empty() && !is_number(row[c])) numeric[c] = false;
  body_ << "<table><thead><tr>";
  for (const auto& h : header) body_ << "<th>" << html_escape(h) << "</th>";
  body_ << "</tr></thead><tbody>\n";
  for (const auto& row : rows) {
    body_ << "<tr>";
    for (std::size_t c = 0; c < row.size(); ++c)
      body_ << (c < numeric.size() && numeric[c] ? "<td class=\"num\">" : "<td>") << html_escape(row[c]) << "</td>";
    body_ << "</tr>\n";
  }
  body_ << "</tbody></table>\n";
}

void HtmlDocument::definition_list(const std::vector<std::pair<std::string, std::string>>& items) {
  body_ << "<dl>";
  for (const auto& [key, value] : items) body_ << "<dt>" << html_escape(key) << "</dt><dd>" << html_escape(value) << "</dd>";
  body_ << "</dl>\n";
}

void HtmlDocument::svg_figure(const std::string& title, const std::string& svg) {
  body_ << "<figure><figcaption>" << html_escape(title) << "</figcaption>\n" << svg << "\n</figure>\n";
}

bool HtmlDocument::png_figure(const std::string& title, const std::filesystem::path& png) {
  const auto bytes = read_file_bytes(png);
  if (!bytes) return false;
  body_ << "<figure><figcaption>" << html_escape(title) << "</figcaption><img alt=\"" << html_escape(title)
        << "\" src=\"data:image/png;base64,";
  append_large(base64(*bytes));
  body_ << "\"></figure>\n";
  return true;
}

void HtmlDocument::png_animation(const std::string& title,
                                 const std::vector<std::pair<std::string, std::string>>& frames) {
  if (frames.empty()) return;
  const std::string id = "fibrodem-slider-" + std::to_string(++slider_count_);
  body_ << "<figure class=\"animation\"><figcaption>" << html_escape(title) << ": <span id=\"" << id << "-label\">"
        << html_escape(frames.front().first) << "</span></figcaption>\n<button type=\"button\" onclick=\"fibrodemPlay('"
        << id << "',this)\">play</button>\n<input type=\"range\" id=\"" << id << "-range\" min=\"0\" max=\""
        << frames.size() - 1 << "\" value=\"0\" aria-label=\"" << html_escape(title) << "\" oninput=\"fibrodemShowFrame('"
        << id << "',this.value)\">\n<div id=\"" << id << "\">";
  for (std::size_t k = 0; k < frames.size(); ++k) {
    body_ << "<img alt=\"" << html_escape(frames[k].first) << "\"" << (k == 0 ? "" : " style=\"display:none\"")
          << " src=\"data:image/png;base64,";
    append_large(base64(frames[k].second));
    body_ << "\">";
  }
  body_ << "</div></figure>\n";
}

void HtmlDocument::details(const std::string& summary, const std::string& text, bool open) {
  body_ << "<details" << (open ? " open" : "") << "><summary>" << html_escape(summary) << "</summary><pre>"
        << html_escape(text) << "</pre></details>\n";
}

// A picture's base64 kept as its own piece: appended to the markup stream it
// would be copied as the stream grows (twice its size at a time).
void HtmlDocument::append_large(std::string text) {
  pieces_.push_back(body_.str());
  body_.str({});
  pieces_.push_back(std::move(text));
}

void HtmlDocument::raw(const std::string& html) { body_ << html; }
void HtmlDocument::begin_row() { body_ << "<div class=\"row\">\n"; }
void HtmlDocument::end_row() { body_ << "</div>\n"; }

// The page around the body, which is written from where it is kept (a page
// of a large tissue's pictures is megabytes: no copy of it is made).
void HtmlDocument::write_to(std::ostream& page) const {
  page << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>" << html_escape(title_)
       << "</title>\n<style>" << kStyle << "</style>\n";
  if (slider_count_ > 0) page << "<script>" << kSliderScript << "</script>\n";
  page << "</head><body>\n<h1>" << html_escape(title_) << "</h1>\n";
  for (const auto& piece : pieces_) page << piece;
  page << body_.view() << "</body></html>\n";
}

std::string HtmlDocument::str() const {
  std::ostringstream page;
  write_to(page);
  return std::move(page).str();
}

void HtmlDocument::write(const std::filesystem::path& file) const {
  const std::filesystem::path temporary = file.string() + ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary);
    write_to(out);
    if (!out.flush()) throw std::runtime_error("cannot write " + temporary.string());
  }
  std::filesystem::rename(temporary, file);
}

}  // namespace fibrodem
