#include <algorithm>
#include <array>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "app/report_sections.hpp"

namespace rodend::report {
namespace fs = std::filesystem;
namespace {

/// The questions a figure answers, in the page's order: the key its PNG carries in the text
/// chunk `rodend-question` (written by python/rodend/analysis/figures.py and
/// plots/plot_study.py) and the heading; figures without the chunk go last.
constexpr std::array<std::array<const char*, 2>, 6> questions{{
    {"rank", "Which factors drive each metric?"},
    {"spread", "How is each metric spread, and how likely is it to pass a limit?"},
    {"surrogate", "Can the surrogate's indices be trusted?"},
    {"histories", "How do the histories spread over time?"},
    {"cases", "What happened in the cases?"},
    {"", "Other figures"},
}};

std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string base64(const std::string& in) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((in.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(in[i]) << 16) |
                       (static_cast<unsigned char>(in[i + 1]) << 8) |
                       static_cast<unsigned char>(in[i + 2]);
    for (int s = 18; s >= 0; s -= 6) out += k[(v >> s) & 63];
  }
  if (i < in.size()) {
    unsigned v = static_cast<unsigned char>(in[i]) << 16;
    if (i + 1 < in.size()) v |= static_cast<unsigned char>(in[i + 1]) << 8;
    out += k[(v >> 18) & 63];
    out += k[(v >> 12) & 63];
    out += i + 1 < in.size() ? k[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

std::string latin1_to_utf8(const std::string& s) {
  std::string out;
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x80) {
      out += c;
    } else {
      out += static_cast<char>(0xC0 | (u >> 6));
      out += static_cast<char>(0x80 | (u & 0x3F));
    }
  }
  return out;
}

/// The uncompressed text chunks (tEXt, iTXt) of a PNG, keyword to UTF-8 text; empty when the
/// bytes are not a PNG. A chunk is length (4 bytes, big-endian), type, data, CRC.
std::map<std::string, std::string> png_texts(const std::string& b) {
  std::map<std::string, std::string> out;
  if (b.compare(0, 8, "\x89PNG\r\n\x1a\n") != 0) return out;
  for (std::size_t at = 8; at + 12 <= b.size();) {
    std::size_t len = 0;
    for (int i = 0; i < 4; ++i) len = len << 8 | static_cast<unsigned char>(b[at + i]);
    const std::string type = b.substr(at + 4, 4);
    if (len > b.size() - at - 12 || type == "IEND") break;
    const std::string data = b.substr(at + 8, len);
    at += 12 + len;
    const std::size_t nul = data.find('\0');
    if (nul == std::string::npos) continue;
    const std::string key = data.substr(0, nul);
    if (type == "tEXt") out[key] = latin1_to_utf8(data.substr(nul + 1));
    if (type != "iTXt" || nul + 2 >= data.size() || data[nul + 1] != 0) continue;
    const std::size_t lang = data.find('\0', nul + 3);
    const std::size_t tkey = lang == std::string::npos ? lang : data.find('\0', lang + 1);
    if (tkey != std::string::npos) out[key] = data.substr(tkey + 1);
  }
  return out;
}

struct Figure {
  fs::path path;
  std::string bytes, caption;
  std::size_t question = questions.size() - 1;
};

std::vector<Figure> read_figures(const fs::path& dir) {
  std::vector<Figure> figs;
  if (!fs::is_directory(dir / "plots")) return figs;
  for (const auto& e : fs::directory_iterator(dir / "plots")) {
    if (e.path().extension() != ".png" || !e.is_regular_file()) continue;
    Figure f{e.path(), read_bytes(e.path()), {}};
    const auto t = png_texts(f.bytes);
    f.caption = t.count("Description") ? t.at("Description") : e.path().stem().string();
    for (std::size_t q = 0; q + 1 < questions.size(); ++q)
      if (t.count("rodend-question") && t.at("rodend-question") == questions[q][0]) f.question = q;
    figs.push_back(std::move(f));
  }
  std::sort(figs.begin(), figs.end(), [](const Figure& a, const Figure& b) {
    return a.question != b.question ? a.question < b.question : a.path < b.path;
  });
  return figs;
}

}  // namespace

void write_figures(std::ostream& h, const fs::path& dir, std::size_t budget) {
  const std::vector<Figure> figs = read_figures(dir);
  h << "<h2>Figures</h2>\n";
  if (figs.empty())
    h << "<p>No figures: draw them first with <code>/usr/bin/python3 plots/plot_study.py "
      << escape(dir.string()) << "</code>.</p>\n";
  std::size_t used = 0, question = questions.size(), left = 0;
  for (const Figure& f : figs) {
    if (f.question != question) {
      question = f.question;
      h << "<h3>" << questions[question][1] << "</h3>\n";
    }
    if (used + f.bytes.size() > budget) {
      ++left;
      h << "<p class=\"more\"><a href=\"" << escape(fs::absolute(f.path).string()) << "\">"
        << escape(f.path.filename().string()) << "</a>: " << escape(f.caption) << "</p>\n";
      continue;
    }
    used += f.bytes.size();
    h << "<figure><img alt=\"" << escape(f.caption) << "\" src=\"data:image/png;base64,"
      << base64(f.bytes) << "\"><figcaption>" << escape(f.caption) << "</figcaption></figure>\n";
  }
  if (left)
    h << "<p class=\"note\">" << left << " figure(s) linked, not embedded: the page embeds "
      << budget / 1000 << " kB of figures at most, to stay small.</p>\n";
}

}  // namespace rodend::report
