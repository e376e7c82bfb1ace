#include "dem/io/checkpoint.h"

#include "dem/io/archive.h"
#include "dem/world/world_io.h"

#include <fcntl.h>
#include <unistd.h>

#include <bit>
#include <cerrno>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <type_traits>

namespace dem {

static_assert(std::endian::native == std::endian::little,
              "checkpoints are written in host byte order and assume a little-endian host");

namespace {

constexpr char kMagic[8] = {'V', 'P', 'P', 'D', 'E', 'M', 'C', 'K'};
constexpr std::size_t kHeader = 8 + 4 + 8;  // magic, version, payload size

uint64_t fnv1a(const char* p, std::size_t n) {
    uint64_t h = 14695981039346656037ull;
    for (std::size_t k = 0; k < n; ++k) {
        h ^= uint8_t(p[k]);
        h *= 1099511628211ull;
    }
    return h;
}

using io::corrupt;
using io::Reader;
using io::Writer;

}  // namespace

void reseal_checkpoint_bytes(std::string& bytes) {
    if (bytes.size() < kHeader + 8) return;
    const uint64_t payload = bytes.size() - kHeader - 8;
    std::memcpy(bytes.data() + 12, &payload, 8);
    const uint64_t sum = fnv1a(bytes.data(), bytes.size() - 8);
    std::memcpy(bytes.data() + bytes.size() - 8, &sum, 8);
}

void save_checkpoint(const std::string& path, const World& w, const std::string& app_state) {
    Writer out;
    out.buf.append(kMagic, 8);
    out.pod(kCheckpointVersion);
    out.pod(uint64_t(0));  // payload size, patched below
    World::serialize(out, w, kCheckpointVersion);
    out.section("APPS", [&](Writer& s) { s.str(app_state); });
    const uint64_t payload = out.buf.size() - kHeader;
    std::memcpy(out.buf.data() + 12, &payload, 8);
    out.pod(fnv1a(out.buf.data(), out.buf.size()));

    const std::string tmp = path + ".part";
    auto fail = [&](const char* what, int fd) {
        const int err = errno;
        if (fd >= 0) ::close(fd);
        std::remove(tmp.c_str());
        throw std::runtime_error(std::string("cannot save checkpoint '") + path + "': " + what + " '" + tmp +
                                 "' failed (" + std::strerror(err) + ")");
    };
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) fail("creating", -1);
    for (std::size_t done = 0; done < out.buf.size();) {
        const ssize_t k = ::write(fd, out.buf.data() + done, out.buf.size() - done);
        if (k < 0 && errno == EINTR) continue;
        if (k <= 0) fail("writing", fd);
        done += std::size_t(k);
    }
    if (::fsync(fd) != 0) fail("syncing", fd);
    if (::close(fd) != 0) fail("closing", -1);
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::remove(tmp.c_str());
        throw std::runtime_error("cannot save checkpoint '" + path + "': renaming '" + tmp + "' failed (" +
                                 ec.message() + ")");
    }
    // Make the rename itself durable (best effort).
    std::string dir = std::filesystem::path(path).parent_path().string();
    if (dir.empty()) dir = ".";
    if (const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); dfd >= 0) {
        ::fsync(dfd);
        ::close(dfd);
    }
}

std::string load_checkpoint(const std::string& path, World& w) {
    std::string buf;
    {
        std::error_code ec;
        if (!std::filesystem::exists(path, ec))
            throw std::runtime_error("cannot open checkpoint '" + path + "': no such file");
        if (std::filesystem::is_directory(path, ec))
            throw std::runtime_error("cannot open checkpoint '" + path + "': is a directory");
        std::ifstream in(path, std::ios::binary);
        if (!in) throw std::runtime_error("cannot open checkpoint '" + path + "': not readable");
        buf.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
        if (in.bad()) throw std::runtime_error("cannot read checkpoint '" + path + "'");
    }
    const std::size_t m = std::min<std::size_t>(buf.size(), 8);
    if (std::memcmp(buf.data(), kMagic, m) != 0)
        throw std::runtime_error("'" + path + "' is not a vppdem checkpoint (bad magic)");
    if (buf.size() < kHeader) corrupt(path, "file has only " + std::to_string(buf.size()) + " bytes");
    uint32_t version;
    std::memcpy(&version, buf.data() + 8, 4);
    uint64_t payload;
    std::memcpy(&payload, buf.data() + 12, 8);
    if (version != kCheckpointVersion && version != 1) {
        // The checksum covers the version too: a file whose sum still holds was written by
        // another (newer) vppdem; one whose sum fails is damaged, and its "version" means nothing
        // (a flipped byte said "format version 3").
        const bool sealed = buf.size() >= kHeader + 8 && buf.size() - kHeader - 8 == payload && [&] {
            uint64_t sum;
            std::memcpy(&sum, buf.data() + kHeader + payload, 8);
            return sum == fnv1a(buf.data(), kHeader + payload);
        }();
        if (!sealed)
            throw std::runtime_error("'" + path + "' is not a vppdem checkpoint of a known version: its header is "
                                     "damaged (version field " + std::to_string(version) +
                                     ", checksum mismatch); this build reads format versions 1 and " +
                                     std::to_string(kCheckpointVersion));
        throw std::runtime_error("checkpoint '" + path + "' was written by another vppdem (format version " +
                                 std::to_string(version) + "); this build reads format versions 1 and " +
                                 std::to_string(kCheckpointVersion) + ": use the vppdem that wrote it");
    }
    if (buf.size() < kHeader + 8 || buf.size() - kHeader - 8 != payload)
        corrupt(path, "size mismatch (file has " + std::to_string(buf.size()) + " bytes, header says " +
                          std::to_string(payload + kHeader + 8) + ")");
    uint64_t sum;
    std::memcpy(&sum, buf.data() + kHeader + payload, 8);
    if (sum != fnv1a(buf.data(), kHeader + payload)) corrupt(path, "checksum mismatch");

    Reader in(buf.data() + kHeader, payload, path);
    World restored;
    World::serialize(in, restored, version);
    std::string app;
    in.section("APPS", [&](Reader& s) { s.str(app); });
    if (!in.done()) corrupt(path, "unexpected data after the last section");
    // World's own consistency rules before anything is derived from the restored state.
    if (const char* why = restored.broken_invariant()) corrupt(path, why);
    restored.rebuild_derived_tables();
    w = std::move(restored);
    return app;
}

}  // namespace dem
