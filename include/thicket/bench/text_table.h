#pragma once
/// A table of text cells rendered either with space-padded columns (terminal) or as Markdown.
#include <string>
#include <vector>

namespace thicket {

class TextTable {
public:
    enum class Align { Left, Right };

    /// A table with these column headers and alignments (same count; throws Error otherwise).
    TextTable(std::vector<std::string> headers, std::vector<Align> align);

    /// Appends a row; it must have one cell per column (throws Error otherwise).
    void add_row(std::vector<std::string> cells);
    size_t rows() const { return rows_.size(); }

    /// Columns padded to their widest cell, two spaces apart, a dashed line under the headers.
    std::string terminal() const;
    /// A GitHub-flavoured Markdown table ('|' in cells escaped, alignment in the separator row).
    std::string markdown() const;

private:
    std::vector<std::string> headers_;
    std::vector<Align> align_;
    std::vector<std::vector<std::string>> rows_;
};

}  // namespace thicket
