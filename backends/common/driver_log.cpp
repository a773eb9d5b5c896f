#include "backends/common/driver_log.h"

#include <algorithm>

namespace omnishadow {
namespace {

std::string_view trimmed(std::string_view s) {
  const auto space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
  while (!s.empty() && space(s.front())) s.remove_prefix(1);
  while (!s.empty() && space(s.back())) s.remove_suffix(1);
  return s;
}

bool separator(std::string_view line) {
  return std::all_of(line.begin(), line.end(),
                     [](char c) { return c == '-' || c == '=' || c == '_' || c == ' '; });
}

std::string bounded(std::string text, std::size_t max_chars) {
  if (text.empty()) return "(no log)";
  if (text.size() <= max_chars) return text;
  const std::size_t left_out = text.size() - max_chars;
  text.resize(max_chars);
  return text + " ... (" + std::to_string(left_out) + " more characters)";
}

void append_lines(std::string_view log, std::string& out) {
  log = log.substr(0, log.find('\0'));
  while (!log.empty()) {
    const std::size_t end = log.find('\n');
    const std::string_view line = trimmed(log.substr(0, end));
    if (!line.empty() && !separator(line)) {
      if (!out.empty()) out += " | ";
      out += line;
    }
    if (end == std::string_view::npos) break;
    log.remove_prefix(end + 1);
  }
}

}  // namespace

std::string one_line_log(std::string_view log, std::size_t max_chars) {
  std::string out;
  append_lines(log, out);
  return bounded(std::move(out), max_chars);
}

std::string one_line_log(const std::vector<std::string>& messages, std::size_t max_chars) {
  std::string out;
  for (const std::string& m : messages) append_lines(m, out);
  return bounded(std::move(out), max_chars);
}

}  // namespace omnishadow
