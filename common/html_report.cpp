#include "common/html_report.h"

#include <algorithm>
#include <cstdint>
#include <sstream>

namespace common {

std::string html_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  return out;
}

std::string base64(const std::string& bytes) {
  static const char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (unsigned(std::uint8_t(bytes[i])) << 16) |
                       (unsigned(std::uint8_t(bytes[i + 1])) << 8) |
                       unsigned(std::uint8_t(bytes[i + 2]));
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += kAlphabet[v & 63];
  }
  if (i < bytes.size()) {
    unsigned v = unsigned(std::uint8_t(bytes[i])) << 16;
    if (i + 1 < bytes.size()) v |= unsigned(std::uint8_t(bytes[i + 1])) << 8;
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

namespace {

std::string png_uri(const std::string& png) {
  return "data:image/png;base64," + base64(png);
}

// The slider's behaviour: each slider's pictures are in a JSON block beside it; moving the
// slider (or playing) swaps the picture's source and the time shown. No library, no network.
const char kSliderScript[] = R"JS(
(function () {
  document.querySelectorAll('.frame-slider').forEach(function (box) {
    var id = box.getAttribute('data-id');
    var frames = JSON.parse(document.getElementById(id + '-data').textContent);
    var slider = document.getElementById(id + '-slider');
    var picture = document.getElementById(id + '-frame');
    var time = document.getElementById(id + '-time');
    var play = document.getElementById(id + '-play');
    var timer = null;
    function show(k) {
      picture.src = frames[k].src;
      time.textContent = 't = ' + frames[k].t.toFixed(2) + ' s (picture ' + (k + 1) + ' of ' +
                         frames.length + ')';
    }
    slider.addEventListener('input', function () { show(Number(slider.value)); });
    play.addEventListener('click', function () {
      if (timer) { clearInterval(timer); timer = null; play.textContent = 'play'; return; }
      play.textContent = 'pause';
      timer = setInterval(function () {
        var k = (Number(slider.value) + 1) % frames.length;
        slider.value = String(k);
        show(k);
      }, 150);
    });
    show(Number(slider.value));
  });
})();
)JS";

const char kStyle[] = R"CSS(
body { font-family: sans-serif; margin: 2em auto; max-width: 980px; color: #222; }
h1 { font-size: 1.6em; } h2 { font-size: 1.25em; margin-top: 1.6em; border-bottom: 1px solid #ccc; }
table { border-collapse: collapse; margin: 0.6em 0; }
th, td { border: 1px solid #bbb; padding: 0.25em 0.7em; text-align: left; }
th { background: #f0f0f0; }
img { max-width: 100%; }
pre { background: #f6f6f6; padding: 0.8em; overflow-x: auto; font-size: 0.85em; }
.frame-slider input[type=range] { width: 70%; vertical-align: middle; }
.frame-slider img { max-height: 80vh; }
)CSS";

}  // namespace

HtmlReport::HtmlReport(std::string title) : title_(std::move(title)) {}

void HtmlReport::heading(const std::string& text) {
  body_ += "<h2>" + html_escape(text) + "</h2>\n";
}

void HtmlReport::paragraph(const std::string& text) {
  body_ += "<p>" + html_escape(text) + "</p>\n";
}

void HtmlReport::table(const std::vector<std::string>& header,
                       const std::vector<std::vector<std::string>>& rows, const std::string& id) {
  std::ostringstream s;
  s << "<table" << (id.empty() ? "" : " id=\"" + html_escape(id) + "\"") << ">\n";
  // A header row of empty names is left out (a table of name-value pairs).
  if (std::any_of(header.begin(), header.end(), [](const std::string& h) { return !h.empty(); })) {
    s << "<tr>";
    for (const auto& h : header) s << "<th>" << html_escape(h) << "</th>";
    s << "</tr>\n";
  }
  for (const auto& row : rows) {
    s << "<tr>";
    for (const auto& cell : row) s << "<td>" << html_escape(cell) << "</td>";
    s << "</tr>\n";
  }
  s << "</table>\n";
  body_ += s.str();
}

void HtmlReport::svg(const std::string& svg_text) {
  const size_t start = svg_text.find("<svg");
  body_ += "<div>" + (start == std::string::npos ? svg_text : svg_text.substr(start)) + "</div>\n";
}

void HtmlReport::picture(const std::string& png, const std::string& alt) {
  body_ += "<p><img alt=\"" + html_escape(alt) + "\" src=\"" + png_uri(png) + "\"></p>\n";
}

void HtmlReport::slider(const std::vector<SliderFrame>& frames, const std::string& id) {
  if (frames.empty()) return;
  has_slider_ = true;
  const std::string i = html_escape(id);
  std::ostringstream s;
  s << "<div class=\"frame-slider\" data-id=\"" << i << "\">\n"
    << "<p><button id=\"" << i
    << "-play\" type=\"button\">play</button> <input type=\"range\" id=\"" << i
    << "-slider\" min=\"0\" max=\"" << frames.size() - 1 << "\" value=\"" << frames.size() - 1
    << "\" step=\"1\"> <span id=\"" << i << "-time\"></span></p>\n<img id=\"" << i
    << "-frame\" alt=\"frame\" src=\"" << png_uri(frames.back().png)
    << "\">\n<script type=\"application/json\" id=\"" << i << "-data\">[";
  for (size_t k = 0; k < frames.size(); ++k)
    s << (k ? ",\n" : "") << "{\"t\":" << frames[k].time_s << ",\"src\":\""
      << png_uri(frames[k].png) << "\"}";
  s << "]</script>\n</div>\n";
  body_ += s.str();
}

void HtmlReport::details(const std::string& summary, const std::string& text) {
  body_ += "<details><summary>" + html_escape(summary) + "</summary><pre>" + html_escape(text) +
           "</pre></details>\n";
}

std::string HtmlReport::html() const {
  std::string out =
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" +
      html_escape(title_) + "</title>\n<style>" + kStyle + "</style>\n</head>\n<body>\n<h1>" +
      html_escape(title_) + "</h1>\n" + body_;
  if (has_slider_) out += std::string("<script>") + kSliderScript + "</script>\n";
  return out + "</body>\n</html>\n";
}

}  // namespace common
