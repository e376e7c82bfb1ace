// The binary archive of everything a run saves to resume (one format for all run state): the
// World's sections (World::serialize, dem/world/world_io.h) and an application's own state
// (e.g. the damper's RunState) are written and read with these two classes, inside a
// checkpoint file (dem/io/checkpoint.h). Numbers are stored as their bytes (host order,
// little-endian: checked by the checkpoint), so every double, NaN and infinity included, reads
// back bit for bit. A Reader checks every count and length against the bytes left and throws
// std::runtime_error "checkpoint 'PATH' is truncated or corrupt: ..." instead of reading past
// them.
#pragma once

#include <cstdint>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace dem::io {

[[noreturn]] inline void corrupt(const std::string& path, const std::string& what) {
    throw std::runtime_error("checkpoint '" + path + "' is truncated or corrupt: " + what);
}

class Writer {
public:
    static constexpr bool kLoading = false;
    std::string buf;

    template <class T> void pod(const T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        buf.append(reinterpret_cast<const char*>(&v), sizeof(T));
    }
    void flag(bool b) { pod(uint8_t(b)); }
    void str(const std::string& s) {
        pod(uint64_t(s.size()));
        buf.append(s);
    }
    template <class T> void vec(const std::vector<T>& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        pod(uint64_t(v.size()));
        buf.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
    }
    void strings(const std::vector<std::string>& v) {
        pod(uint64_t(v.size()));
        for (const std::string& s : v) str(s);
    }
    void numbers(const std::map<std::string, double>& m) {
        pod(uint64_t(m.size()));
        for (const auto& [k, v] : m) {
            str(k);
            pod(v);
        }
    }
    template <class T, class F> void list(const std::vector<T>& v, F&& each) {
        pod(uint64_t(v.size()));
        for (const T& e : v) each(*this, e);
    }
    // A section that only some files have: written when `present`.
    template <class F> void optional_section(const char (&tag)[5], bool present, F&& body) {
        if (present) section(tag, body);
    }
    template <class F> void section(const char (&tag)[5], F&& body) {
        buf.append(tag, 4);
        const std::size_t at = buf.size();
        pod(uint64_t(0));
        body(*this);
        const uint64_t len = buf.size() - at - 8;
        std::memcpy(buf.data() + at, &len, 8);
    }
};

class Reader {
public:
    static constexpr bool kLoading = true;
    Reader(const char* p, std::size_t n, const std::string& path) : p_(p), end_(p + n), path_(path) {}

    template <class T> void pod(T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        need(sizeof(T));
        std::memcpy(&v, p_, sizeof(T));
        p_ += sizeof(T);
    }
    void flag(bool& b) {
        uint8_t v;
        pod(v);
        if (v > 1) corrupt(path_, "bad boolean");
        b = v;
    }
    void str(std::string& s) {
        const uint64_t n = count(1);
        s.assign(p_, n);
        p_ += n;
    }
    template <class T> void vec(std::vector<T>& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        const uint64_t n = count(sizeof(T));
        v.resize(n);
        if (n) std::memcpy(v.data(), p_, n * sizeof(T));
        p_ += n * sizeof(T);
    }
    void strings(std::vector<std::string>& v) {
        v.assign(count(8), std::string{});  // each string takes at least its length
        for (std::string& s : v) str(s);
    }
    void numbers(std::map<std::string, double>& m) {
        m.clear();
        const uint64_t n = count(16);  // a key's length and a value
        for (uint64_t k = 0; k < n; ++k) {
            std::string key;
            double v;
            str(key);
            pod(v);
            m[key] = v;
        }
    }
    template <class T, class F> void list(std::vector<T>& v, F&& each) {
        v.assign(count(1), T{});  // every element takes at least one byte
        for (T& e : v) each(*this, e);
    }
    template <class F> void section(const char (&tag)[5], F&& body) {
        need(12);
        if (std::memcmp(p_, tag, 4) != 0)
            corrupt(path_, "expected section '" + std::string(tag) + "', found '" + std::string(p_, 4) + "'");
        uint64_t len;
        std::memcpy(&len, p_ + 4, 8);
        p_ += 12;
        if (len > uint64_t(end_ - p_)) corrupt(path_, "section '" + std::string(tag) + "' overruns the file");
        Reader sub(p_, len, path_);
        body(sub);
        if (sub.p_ != sub.end_) corrupt(path_, "section '" + std::string(tag) + "' has unread bytes");
        p_ += len;
    }
    // Read when the next section has this tag.
    template <class F> void optional_section(const char (&tag)[5], bool /*present*/, F&& body) {
        if (end_ - p_ >= 4 && std::memcmp(p_, tag, 4) == 0) section(tag, body);
    }
    bool done() const { return p_ == end_; }
    const std::string& path() const { return path_; }  // the file (for messages)

private:
    void need(std::size_t n) const {
        if (n > std::size_t(end_ - p_)) corrupt(path_, "record runs past the end of its section");
    }
    // Reads an element count and checks that count * size bytes are left.
    uint64_t count(std::size_t size) {
        uint64_t n;
        pod(n);
        if (n > uint64_t(end_ - p_) / size) corrupt(path_, "element count runs past the end of its section");
        return n;
    }

    const char* p_;
    const char* end_;
    const std::string& path_;
};

}  // namespace dem::io
