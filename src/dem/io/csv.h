// CSV output written under a temporary name and renamed into place when closed, so a reader
// never sees a half-written file under the final name; and CSV input of sphere lists.
#pragma once

#include <array>
#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace dem {

class CsvWriter {
public:
    CsvWriter() = default;
    CsvWriter(const std::string& path, std::string_view header) { open(path, header); }
    // Closes the file (see close()); during an exception's unwinding discards it instead.
    ~CsvWriter();
    CsvWriter(const CsvWriter&) = delete;
    CsvWriter& operator=(const CsvWriter&) = delete;

    void open(const std::string& path, std::string_view header);
    // Appends one row; numbers in shortest round-trip form.
    void row(std::initializer_list<double> values);
    void row(const std::vector<double>& values);
    void flush();
    // Flush, then rename PATH.part -> PATH. A failed write (a full disk) removes PATH.part and
    // throws std::runtime_error; PATH is then left as it was.
    void close();

private:
    std::string path_;
    std::FILE* file_ = nullptr;
    std::string buf_;
    int unwinding_ = 0;  // std::uncaught_exceptions() when opened

    [[noreturn]] void fail(const char* what);  // discard(), then throw naming the file and errno
    void discard() noexcept;                   // close and remove PATH.part
};

// Appends the shortest decimal form of v that reads back to the same double.
void append_number(std::string& out, double v);

// Cells of CSV text built by hand (rows that mix words and numbers: a study's summary.csv):
// a number in shortest round-trip form, empty when not finite (a missing value, not "nan");
// a word as it is, quoted ("" for a quote) when it holds a comma, a quote or a line break,
// line breaks becoming spaces so that one row stays one line.
std::string csv_number(double v);
std::string csv_text(const std::string& s);

// Reads rows of numbers from a CSV file (comma separated; an optional first line that is not
// numeric is taken as a header; blank lines and lines starting with '#' are skipped). Every row
// must have at least `min_columns` values. Throws std::runtime_error naming path and line.
std::vector<std::vector<double>> read_numeric_csv(const std::string& path, std::size_t min_columns,
                                                  std::vector<std::string>* header = nullptr);

// Writes `text` to `path` atomically (temporary file, then rename).
void write_text_atomic(const std::string& path, const std::string& text);
// The bytes of the file at `path` ("" when it cannot be read).
std::string read_text(const std::string& path);
// Copies `from` to `to` (its folder made) atomically when their bytes differ or `to` is missing:
// a results folder republished with the same records keeps its files as they were. Returns
// whether it wrote.
bool copy_text_if_changed(const std::string& from, const std::string& to);
inline bool copy_text_if_changed(const std::filesystem::path& from, const std::filesystem::path& to) {
    return copy_text_if_changed(from.string(), to.string());
}

}  // namespace dem
