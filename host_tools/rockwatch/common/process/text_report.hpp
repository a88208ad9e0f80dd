// Text helpers the commands' reports share: printf-style formatting, the "  label  text" line, and the record
// naming used in summaries.
#pragma once

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "rockwatch/core/design_spectrum.hpp"

namespace rockwatch::cli {

// printf into a std::string.
#if defined(__GNUC__)
__attribute__((format(printf, 1, 2)))
#endif
std::string format(const char* fmt, ...);

// One "Label  text" line; labels share a column so the eye can run down them.
void line(std::string& out, const char* label, const std::string& text);

// The value, or JSON null when it is absent.
nlohmann::ordered_json number_or_null(const std::optional<double>& value);

// "t = 1.2345 s", or `when_absent`.
std::string time_text(const std::optional<double>& t_s, const char* when_absent);

// The last component of a '/'-separated path.
std::string file_name(const std::string& path);

// A record format id as readers know it ("peer-at2", "plain", "esm", "itaca-cor-acc", "miniseed",
// "rockwatch-suite"), as people know it; an unknown id as it is.
std::string format_name(const std::string& format_id);

// A command-line argument as a POSIX shell reads it back: as is when it is plain, else in single quotes.
std::string shell_quoted(const std::string& argument);

// "npr9998-2015: p 2.5, TB 0.15 s, TC 0.4 s, TD 0.67 s".
std::string spectrum_text(const core::SpectrumShape& s);

// Header text comes from the file: control characters must not reach the terminal.
std::string printable(std::string text);

}  // namespace rockwatch::cli
