#pragma once
// Markdown tables as every report writes them: each cell escaped so that its text cannot split the row (a `|` in
// "max |dbeta|" or in a file name would otherwise start a new cell), the rows built from cells rather than by
// hand-placed bars. Pure text; no units (the caller's headers carry them).
#include <string>
#include <vector>

namespace pushpred {

/// `text` as one Markdown table cell: `|` written as `\|`, a backslash before it kept, line breaks as spaces.
std::string markdown_cell(const std::string& text);

/// `value` printed with the printf `format` (one double), for a table: a value that rounds to zero is printed without
/// its sign ("0.0", never "-0.0").
std::string table_number(const char* format, double value);

/// One table row, "| a | b |\n", every cell escaped with markdown_cell.
std::string markdown_row(const std::vector<std::string>& cells);

/// The header row and its separator: "| a | b |\n|---|---|\n"; `alignment` per column, "---" (default), "---:" or
/// ":---" (shorter than the header, the rest default).
std::string markdown_header(const std::vector<std::string>& cells, const std::vector<std::string>& alignment = {});

}  // namespace pushpred
