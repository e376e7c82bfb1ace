#include "dem/io/csv.h"

#include <charconv>
#include <cerrno>
#include <cmath>
#include <exception>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace dem {

void append_number(std::string& out, double v) {
    char tmp[32];
    auto res = std::to_chars(tmp, tmp + sizeof tmp, v);
    out.append(tmp, res.ptr);
}

std::string csv_number(double v) {
    std::string s;
    if (std::isfinite(v)) append_number(s, v);
    return s;
}

std::string csv_text(const std::string& s) {
    if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
    std::string out = "\"";
    for (char c : s) {
        if (c == '"') out += "\"\"";
        else if (c == '\n' || c == '\r') out += ' ';
        else out += c;
    }
    return out + "\"";
}

void CsvWriter::open(const std::string& path, std::string_view header) {
    close();
    unwinding_ = std::uncaught_exceptions();
    path_ = path;
    file_ = std::fopen((path + ".part").c_str(), "wb");
    if (!file_) throw std::runtime_error("cannot write '" + path + ".part': " + std::strerror(errno));
    buf_.assign(header);
    buf_ += '\n';
}

void CsvWriter::row(std::initializer_list<double> values) {
    bool first = true;
    for (double v : values) {
        if (!first) buf_ += ',';
        first = false;
        append_number(buf_, v);
    }
    buf_ += '\n';
    if (buf_.size() > (1u << 20)) flush();
}

void CsvWriter::row(const std::vector<double>& values) {
    for (std::size_t k = 0; k < values.size(); ++k) {
        if (k) buf_ += ',';
        append_number(buf_, values[k]);
    }
    buf_ += '\n';
    if (buf_.size() > (1u << 20)) flush();
}

void CsvWriter::flush() {
    if (!file_) return;
    // A full disk shows at fwrite or only at fflush (the C library's buffer): both are checked,
    // so a short file is never renamed into place as if it were complete.
    if (!buf_.empty() && std::fwrite(buf_.data(), 1, buf_.size(), file_) != buf_.size()) fail("write failed");
    buf_.clear();
    if (std::fflush(file_) != 0) fail("write failed");
}

void CsvWriter::fail(const char* what) {
    const int err = errno;
    discard();
    throw std::runtime_error(std::string(what) + " for '" + path_ + ".part' (" + std::strerror(err) + "): '" + path_ +
                             "' was not written (a full disk?)");
}

void CsvWriter::discard() noexcept {
    if (!file_) return;
    std::fclose(file_);
    file_ = nullptr;
    buf_.clear();
    std::error_code ec;
    std::filesystem::remove(path_ + ".part", ec);
}

void CsvWriter::close() {
    if (!file_) return;
    flush();
    // fclose writes what is left in the C library's buffer: its result counts as much.
    std::FILE* f = file_;
    file_ = nullptr;
    if (std::fclose(f) != 0) {
        const int err = errno;
        std::error_code ec;
        std::filesystem::remove(path_ + ".part", ec);
        throw std::runtime_error("write failed for '" + path_ + ".part' (" + std::strerror(err) + "): '" + path_ +
                                 "' was not written (a full disk?)");
    }
    std::filesystem::rename(path_ + ".part", path_);
}

CsvWriter::~CsvWriter() {
    // A destructor must not throw (an exception during another's unwinding ends the process,
    // exit 134): a writer left open by an exception is discarded (no half file under the final
    // name); one left open on an ordinary exit is closed, and a failure to close is reported
    // and the file discarded.
    if (!file_) return;
    if (std::uncaught_exceptions() > unwinding_) {
        discard();
        return;
    }
    try {
        close();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "vppdem: error: %s\n", e.what());
    }
}

std::vector<std::vector<double>> read_numeric_csv(const std::string& path, std::size_t min_columns,
                                                  std::vector<std::string>* header) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot read CSV file '" + path + "'");
    std::vector<std::vector<double>> rows;
    std::string line;
    std::size_t lineno = 0;
    while (std::getline(in, line)) {
        ++lineno;
        // A UTF-8 byte order mark is no part of the first cell (a header "size" would not match).
        if (lineno == 1 && line.starts_with("\xEF\xBB\xBF")) line.erase(0, 3);
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.empty() || line[0] == '#') continue;
        std::vector<double> vals;
        std::vector<std::string> cells;
        std::stringstream ss(line);
        std::string cell;
        bool numeric = true;
        while (std::getline(ss, cell, ',')) {
            const auto b = cell.find_first_not_of(" \t"), e = cell.find_last_not_of(" \t");
            cell = b == std::string::npos ? "" : cell.substr(b, e - b + 1);
            cells.push_back(cell);
            double v = 0;
            const char* s = cell.data();
            if (!cell.empty() && *s == '+') ++s;
            auto r = std::from_chars(s, cell.data() + cell.size(), v);
            if (cell.empty() || r.ec != std::errc() || r.ptr != cell.data() + cell.size()) numeric = false;
            vals.push_back(v);
        }
        if (!numeric) {
            if (rows.empty() && header && header->empty()) {
                *header = cells;
                continue;
            }
            if (rows.empty() && !header) continue;  // a header nobody asked for
            throw std::runtime_error("CSV file '" + path + "' line " + std::to_string(lineno) +
                                     ": not a number in '" + line + "'");
        }
        if (vals.size() < min_columns)
            throw std::runtime_error("CSV file '" + path + "' line " + std::to_string(lineno) + ": " +
                                     std::to_string(vals.size()) + " columns, need at least " +
                                     std::to_string(min_columns));
        rows.push_back(std::move(vals));
    }
    return rows;
}

void write_text_atomic(const std::string& path, const std::string& text) {
    const std::string tmp = path + ".part";
    {
        std::ofstream out(tmp, std::ios::binary);
        if (!out) throw std::runtime_error("cannot write '" + tmp + "'");
        out << text;
        // The stream's buffer reaches the disk at close: a full disk shows there, and the old
        // file must then stay as it was.
        out.close();
        if (!out) {
            std::error_code ec;
            std::filesystem::remove(tmp, ec);
            throw std::runtime_error("write failed for '" + tmp + "': '" + path + "' was not replaced (a full disk?)");
        }
    }
    std::filesystem::rename(tmp, path);
}

std::string read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

bool copy_text_if_changed(const std::string& from, const std::string& to) {
    const std::string text = read_text(from);
    if (std::filesystem::exists(to) && read_text(to) == text) return false;
    std::filesystem::create_directories(std::filesystem::path(to).parent_path());
    write_text_atomic(to, text);
    return true;
}

}  // namespace dem
