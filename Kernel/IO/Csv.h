// A tiny, strict CSV reader/writer for numeric tables (material tables, reference curves, ...).
//
// Format: lines starting with '#' are comments; blank lines are ignored; the first other line is
// the header (comma-separated column names); every following line has exactly one finite number
// per column. No quoting. Spaces around cells are ignored; CRLF line ends are accepted.
// Errors throw pdpm::InputError "FILE:LINE: message".
#pragma once
#include <string>
#include <vector>

namespace pdpm {

struct CsvTable {
    std::vector<std::string> columns;
    std::vector<std::vector<double>> rows;
    /// Only when parsed with a label column: its header name (not in `columns`) and each row's label.
    std::string labelColumn;
    std::vector<std::string> labels;
    std::vector<long> rowLines;  ///< line number (1-based) of each row in the source, for messages
    std::string source;  ///< file it was read from (for error messages); may be empty

    /// Index of the named column; throws InputError naming the file and the available columns if
    /// there is no such column.
    int column(const std::string& name) const;
    bool hasColumn(const std::string& name) const;
    /// All values of one column.
    std::vector<double> columnValues(const std::string& name) const;
};

/// Reads a file (InputError if missing or malformed). With `labelColumn` the first column holds a
/// non-empty text label per row (e.g. a parameter name) and the other columns numbers.
CsvTable readCsv(const std::string& path, bool labelColumn = false);
/// Parses CSV text; `source` names it in error messages.
CsvTable parseCsv(const std::string& text, const std::string& source, bool labelColumn = false);

/// Writes a table atomically (AtomicOFStream) with 17 significant digits, so that readCsv returns
/// exactly the same numbers. Optional comment lines are written first, each prefixed by "# ".
/// Throws InputError on ragged rows, bad column names, or write errors.
void writeCsv(const std::string& path, const std::vector<std::string>& columns,
              const std::vector<std::vector<double>>& rows,
              const std::vector<std::string>& comments = {});

} // namespace pdpm
