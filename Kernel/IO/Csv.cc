#include "IO/Csv.h"

#include "Core/Error.h"
#include "Core/Parameters.h"
#include "IO/AtomicFile.h"

#include <algorithm>
#include <cctype>
#include <cmath>

namespace pdpm {

namespace {

std::string trim(const std::string& s) {
    const auto b = s.find_first_not_of(" \t");
    if (b == std::string::npos) return {};
    const auto e = s.find_last_not_of(" \t");
    return s.substr(b, e - b + 1);
}

std::vector<std::string> splitCells(const std::string& line) {
    std::vector<std::string> cells;
    std::size_t start = 0;
    while (true) {
        const auto comma = line.find(',', start);
        cells.push_back(trim(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return cells;
}

std::string where(const std::string& source, long line) {
    return (source.empty() ? std::string("<csv>") : source) + ":" + std::to_string(line) + ": ";
}

} // namespace

int CsvTable::column(const std::string& name) const {
    for (std::size_t i = 0; i < columns.size(); ++i)
        if (columns[i] == name) return static_cast<int>(i);
    std::string list;
    for (const auto& c : columns) list += (list.empty() ? "" : ", ") + c;
    throw InputError((source.empty() ? std::string("CSV table") : source) + ": no column '" + name +
                     "' (columns: " + list + ")");
}

bool CsvTable::hasColumn(const std::string& name) const {
    return std::find(columns.begin(), columns.end(), name) != columns.end();
}

std::vector<double> CsvTable::columnValues(const std::string& name) const {
    const int c = column(name);
    std::vector<double> v;
    v.reserve(rows.size());
    for (const auto& r : rows) v.push_back(r[static_cast<std::size_t>(c)]);
    return v;
}

CsvTable parseCsv(const std::string& text, const std::string& source, bool labelColumn) {
    CsvTable t;
    t.source = source;
    bool haveHeader = false;
    long lineNo = 0;
    std::size_t pos = 0;
    while (pos < text.size()) {
        auto nl = text.find('\n', pos);
        std::string line = text.substr(pos, nl == std::string::npos ? std::string::npos : nl - pos);
        pos = nl == std::string::npos ? text.size() : nl + 1;
        ++lineNo;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        const std::string stripped = trim(line);
        if (stripped.empty() || stripped[0] == '#') continue;
        if (line.find('"') != std::string::npos)
            throw InputError(where(source, lineNo) + "quoted cells are not supported");
        auto cells = splitCells(line);
        if (!haveHeader) {
            for (std::size_t i = 0; i < cells.size(); ++i) {
                if (cells[i].empty())
                    throw InputError(where(source, lineNo) + "empty column name in header (column " +
                                     std::to_string(i + 1) + ")");
                for (std::size_t j = 0; j < i; ++j)
                    if (cells[j] == cells[i])
                        throw InputError(where(source, lineNo) + "duplicate column name '" + cells[i] + "'");
            }
            if (labelColumn) {
                t.labelColumn = cells.front();
                cells.erase(cells.begin());
            }
            t.columns = std::move(cells);
            haveHeader = true;
            continue;
        }
        const std::size_t expected = t.columns.size() + (labelColumn ? 1 : 0);
        if (cells.size() != expected)
            throw InputError(where(source, lineNo) + "expected " + std::to_string(expected) + " cells, found " +
                             std::to_string(cells.size()));
        if (labelColumn) {
            if (cells.front().empty()) throw InputError(where(source, lineNo) + "empty label in column '" + t.labelColumn + "'");
            t.labels.push_back(cells.front());
            cells.erase(cells.begin());
        }
        std::vector<double> row(cells.size());
        for (std::size_t i = 0; i < cells.size(); ++i) {
            if (!parseStrictDouble(cells[i], row[i])) {
                std::string lower = cells[i];
                std::transform(lower.begin(), lower.end(), lower.begin(),
                               [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
                const bool isNan = lower.find("nan") != std::string::npos;
                throw InputError(where(source, lineNo) + "column '" + t.columns[i] + "': " +
                                 (isNan ? std::string("NaN is not allowed")
                                        : "'" + cells[i] + "' is not a finite number"));
            }
        }
        t.rows.push_back(std::move(row));
        t.rowLines.push_back(lineNo);
    }
    if (!haveHeader) throw InputError((source.empty() ? std::string("<csv>") : source) + ": no header line");
    return t;
}

CsvTable readCsv(const std::string& path, bool labelColumn) { return parseCsv(readWholeFile(path), path, labelColumn); }

void writeCsv(const std::string& path, const std::vector<std::string>& columns,
              const std::vector<std::vector<double>>& rows, const std::vector<std::string>& comments) {
    if (columns.empty()) throw InputError(path + ": a CSV table needs at least one column");
    for (const auto& c : columns)
        if (c.empty() || c != trim(c) || c.find_first_of(",\"\n\r#") != std::string::npos)
            throw InputError(path + ": invalid CSV column name '" + c + "'");
    for (std::size_t r = 0; r < rows.size(); ++r)
        if (rows[r].size() != columns.size())
            throw InputError(path + ": row " + std::to_string(r) + " has " + std::to_string(rows[r].size()) +
                             " values for " + std::to_string(columns.size()) + " columns");
    AtomicOFStream out(path);
    for (const auto& c : comments) {
        std::string line = c;
        std::replace(line.begin(), line.end(), '\n', ' ');
        out << "# " << line << '\n';
    }
    for (std::size_t i = 0; i < columns.size(); ++i) out << (i ? "," : "") << columns[i];
    out << '\n';
    for (const auto& row : rows) {
        for (std::size_t i = 0; i < row.size(); ++i) {
            if (!std::isfinite(row[i]))
                throw InputError(path + ": refusing to write non-finite value in column '" + columns[i] + "'");
            out << (i ? "," : "") << formatDouble(row[i]);
        }
        out << '\n';
    }
    out.commit();
}

} // namespace pdpm
