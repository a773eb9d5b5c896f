#pragma once
// A driver's log (a GLSL compiler's or linker's info log, the validation layer's messages) as one line that
// keeps every message: a case's reason is printed one line a case on the console and in the summary, and
// stored in results.json. NVIDIA's link log reads "Link info", a dashes line, then the messages: a reason cut
// at the first line said only "Link info".
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace omnishadow {

// Long enough for a few dozen compiler messages; a log past it ends with how much was left out.
inline constexpr std::size_t kDriverLogMaxChars = 4000;

// Every non-empty line of `log`, trimmed, separator lines (dashes, equals signs) dropped, joined with " | ";
// NUL bytes end the text (GL counts the terminator in its log length). At most `max_chars` characters of it
// are kept, then " ... (N more characters)". An empty log gives "(no log)".
std::string one_line_log(std::string_view log, std::size_t max_chars = kDriverLogMaxChars);

// Several messages (the validation layer's, in order) the same way: all of them, one line, bounded.
std::string one_line_log(const std::vector<std::string>& messages,
                         std::size_t max_chars = kDriverLogMaxChars);

}  // namespace omnishadow
