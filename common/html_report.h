#pragma once
// A report as one HTML file that opens from disk with no server and no network: headings, text,
// tables, inline SVG plots, PNG pictures as data URIs, and a time slider over a series of
// pictures. Its only script is written here and embedded in the file; nothing is fetched when it
// is viewed.

#include <string>
#include <vector>

namespace common {

// `text` with &, <, >, " and ' escaped, for element content and attribute values.
std::string html_escape(const std::string& text);

// Standard base64 (RFC 4648, with padding) of `bytes`.
std::string base64(const std::string& bytes);

struct SliderFrame {
  double time_s = 0;
  std::string png;  // the picture's PNG bytes
};

class HtmlReport {
 public:
  explicit HtmlReport(std::string title);

  void heading(const std::string& text);
  void paragraph(const std::string& text);
  // A table with a header row (left out when every name is empty); `id` (optional) names it
  // for readers and tests.
  void table(const std::vector<std::string>& header,
             const std::vector<std::vector<std::string>>& rows, const std::string& id = "");
  // An SVG document's text, inlined (its XML prolog, if any, dropped).
  void svg(const std::string& svg_text);
  void picture(const std::string& png, const std::string& alt);
  // The pictures behind a slider (and a play button) that shows one at a time with its time,
  // the last first;
  // `id` names the slider ("<id>-slider"), its picture ("<id>-frame") and time ("<id>-time").
  void slider(const std::vector<SliderFrame>& frames, const std::string& id);
  // A collapsed block of preformatted text (settings, JSON).
  void details(const std::string& summary, const std::string& text);

  std::string html() const;

 private:
  std::string title_;
  std::string body_;
  bool has_slider_ = false;
};

}  // namespace common
