#include "thicket/bench/text_table.h"

#include <algorithm>

#include "thicket/core/error.h"

namespace thicket {

namespace {

// Display width: count UTF-8 code points, not bytes, so that a "x" or dash sign lines up.
size_t display_width(const std::string& s) {
    size_t w = 0;
    for (unsigned char c : s) w += (c & 0xC0) != 0x80;
    return w;
}

std::string markdown_cell(const std::string& s) {
    std::string out;
    for (char c : s) {
        if (c == '|') out += '\\';
        out += c;
    }
    return out;
}

}  // namespace

TextTable::TextTable(std::vector<std::string> headers, std::vector<Align> align)
    : headers_(std::move(headers)), align_(std::move(align)) {
    if (headers_.size() != align_.size()) throw Error("TextTable: one alignment per column is needed");
}

void TextTable::add_row(std::vector<std::string> cells) {
    if (cells.size() != headers_.size())
        throw Error("TextTable: row of " + std::to_string(cells.size()) + " cells in a table of " +
                    std::to_string(headers_.size()) + " columns");
    rows_.push_back(std::move(cells));
}

std::string TextTable::terminal() const {
    std::vector<size_t> width(headers_.size());
    for (size_t c = 0; c < headers_.size(); ++c) {
        width[c] = display_width(headers_[c]);
        for (const auto& row : rows_) width[c] = std::max(width[c], display_width(row[c]));
    }
    auto line = [&](const std::vector<std::string>& cells) {
        std::string out;
        for (size_t c = 0; c < cells.size(); ++c) {
            const std::string pad(width[c] - display_width(cells[c]), ' ');
            if (c) out += "  ";
            out += align_[c] == Align::Right ? pad + cells[c] : cells[c] + (c + 1 < cells.size() ? pad : "");
        }
        return out + "\n";
    };
    std::string out = line(headers_);
    size_t total = 0;
    for (size_t c = 0; c < width.size(); ++c) total += width[c] + (c ? 2 : 0);
    out += std::string(total, '-') + "\n";
    for (const auto& row : rows_) out += line(row);
    return out;
}

std::string TextTable::markdown() const {
    auto line = [](const std::vector<std::string>& cells) {
        std::string out = "|";
        for (const std::string& c : cells) {
            out += ' ';
            out += markdown_cell(c);
            out += " |";
        }
        return out + "\n";
    };
    std::string out = line(headers_) + "|";
    for (Align a : align_) out += a == Align::Right ? "---:|" : "---|";
    out += "\n";
    for (const auto& row : rows_) out += line(row);
    return out;
}

}  // namespace thicket
