// One self-contained HTML page, built section by section: inline CSS, inline
// SVG, pictures as base64 data URIs, no network and no external scripts, so a
// report opens offline in any browser and can be mailed as one file.
#pragma once

#include <filesystem>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace fibrodem {

// Text made safe inside HTML elements and attribute values.
std::string html_escape(const std::string& text);
// RFC 4648 base64.
std::string base64(const std::string& bytes);
// A file's bytes in one read (a picture to embed); nullopt if it cannot be read.
std::optional<std::string> read_file_bytes(const std::filesystem::path& file);

class HtmlDocument {
 public:
  explicit HtmlDocument(std::string title);

  void heading(int level, const std::string& text, const std::string& id = "");
  void paragraph(const std::string& text);
  // A prominent box: kind "error" (red) or "warning" (amber); `lines` each a list item.
  void notice(const std::string& kind, const std::string& title, const std::vector<std::string>& lines);
  // Columns whose cells all read as numbers are right-aligned.
  void table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows);
  // Key/value pairs, e.g. the scene's settings.
  void definition_list(const std::vector<std::pair<std::string, std::string>>& items);
  // A titled figure around SVG markup (io/plot_svg).
  void svg_figure(const std::string& title, const std::string& svg);
  // A titled figure showing a PNG file, embedded as a data URI; false (and
  // nothing added) if the file cannot be read.
  bool png_figure(const std::string& title, const std::filesystem::path& png);
  // Pictures in time order under one slider (snapshots), from PNG bytes
  // (label, bytes): one <img> shown at a time, switched by a range input or
  // played in a loop by a play/pause button (inline script), the frames kept
  // as data URIs in the page.
  void png_animation(const std::string& title, const std::vector<std::pair<std::string, std::string>>& frames);
  // Preformatted text folded away (a manifest, a log), open if asked.
  void details(const std::string& summary, const std::string& text, bool open = false);
  // Markup written by the caller (already escaped).
  void raw(const std::string& html);
  void begin_row();  // figures side by side until end_row()
  void end_row();

  std::string str() const;
  void write_to(std::ostream& page) const;
  // Written to a temporary file and renamed: a reader never sees half a page.
  void write(const std::filesystem::path& file) const;

 private:
  void append_large(std::string text);

  std::string title_;
  // The body: whole pieces (markup, then each picture's base64), and the
  // markup since the last picture.
  std::vector<std::string> pieces_;
  std::ostringstream body_;
  int slider_count_ = 0;
};

}  // namespace fibrodem
