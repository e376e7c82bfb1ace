#include "dem/io/folder_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

namespace dem {

namespace {

constexpr std::size_t kMaxCommand = 240;  // characters of the holder's command line in a refusal

// What the holder writes into the lock file, one "key value" line each.
std::string holder_text() {
    char host[256] = "";
    if (::gethostname(host, sizeof host - 1) != 0) host[0] = '\0';
    char when[32] = "";
    const std::time_t now = std::time(nullptr);
    std::tm tm{};
    if (::localtime_r(&now, &tm)) std::strftime(when, sizeof when, "%Y-%m-%d %H:%M:%S", &tm);
    // Linux only; elsewhere the refusal names the pid and host without the command.
    std::ifstream in("/proc/self/cmdline", std::ios::binary);
    std::string cmd((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    for (char& c : cmd)
        if (c == '\0' || c == '\n') c = ' ';
    while (!cmd.empty() && cmd.back() == ' ') cmd.pop_back();
    return "pid " + std::to_string(::getpid()) + "\nhost " + host + "\nstarted " + when + "\ncommand " + cmd + "\n";
}

std::string read_all(int fd) {
    std::string s;
    char buf[4096];
    off_t at = 0;
    for (ssize_t n; s.size() < 65536 && (n = ::pread(fd, buf, sizeof buf, at)) > 0; at += n) s.append(buf, std::size_t(n));
    return s;
}

std::string refusal(const std::string& dir, const std::string& path, const std::string& holder) {
    std::string pid, host, started, command;
    std::istringstream in(holder);
    for (std::string line; std::getline(in, line);) {
        const auto sp = line.find(' ');
        const std::string key = line.substr(0, sp), value = sp == std::string::npos ? "" : line.substr(sp + 1);
        if (key == "pid") pid = value;
        else if (key == "host") host = value;
        else if (key == "started") started = value;
        else if (key == "command") command = value;
    }
    std::string who;
    if (pid.empty()) {
        // Between the holder's lock and its writing its name: rare, and still a refusal.
        who = "another process (it has not written its name into " + path + " yet)";
    } else {
        // This process itself: another FolderLock of it holds the folder (a Python Damper not
        // yet deleted, say); flock does not tell one's own locks apart from others'.
        char me[256] = "";
        const bool self = pid == std::to_string(::getpid()) && ::gethostname(me, sizeof me - 1) == 0 && host == me;
        who = std::string(self ? "another run of this process" : "another run") + " (pid " + pid;
        if (!host.empty()) who += " on host " + host;
        if (!started.empty()) who += ", started " + started;
        if (command.size() > kMaxCommand) command = command.substr(0, kMaxCommand) + " ...";
        if (!command.empty()) who += ": " + command;
        who += ")";
    }
    return "folder '" + dir + "' is in use by " + who +
           "; one run at a time writes into a folder: wait for that one to end or stop it, or choose another folder";
}

bool same_file(int fd, const std::string& path) {
    struct stat a {}, b {};
    return ::fstat(fd, &a) == 0 && ::stat(path.c_str(), &b) == 0 && a.st_dev == b.st_dev && a.st_ino == b.st_ino;
}

}  // namespace

FolderLock::FolderLock(const std::string& dir) {
    if (!std::filesystem::is_directory(dir)) throw std::runtime_error("cannot lock '" + dir + "': no such folder");
    const std::string path = (std::filesystem::path(dir) / kFileName).string();
    // A holder removes the file as it releases the lock. Between our open() and our flock() it
    // may have done so: the lock we then get is on a file no longer at `path`, which a third
    // process would create anew and lock too. So the lock counts only while `path` is still the
    // file locked; otherwise open again (each round means a holder released meanwhile).
    for (int round = 0;; ++round) {
        // O_CLOEXEC: the plots' std::system() children must not inherit the lock and hold it
        // after this process ends.
        // O_NOFOLLOW: the lock is truncated and written below; a lock file that is a symbolic
        // link would have that done to whatever it points to (a user's file), so it is refused.
        const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
        if (fd < 0 && errno == ELOOP)
            throw std::runtime_error("the lock file '" + path + "' is a symbolic link; vppdem writes into its lock "
                                     "file and will not follow a link to another file: remove the link");
        if (fd < 0) throw std::runtime_error("cannot create the lock file '" + path + "': " + std::strerror(errno));
        int rc;
        do rc = ::flock(fd, LOCK_EX | LOCK_NB);
        while (rc != 0 && errno == EINTR);
        if (rc != 0) {
            const int err = errno;
            if (err == EWOULDBLOCK) {
                const std::string holder = read_all(fd);
                ::close(fd);
                throw FolderLocked(refusal(dir, path, holder));
            }
            ::close(fd);
            if (err == ENOLCK || err == EOPNOTSUPP || err == ENOSYS) {
                ::unlink(path.c_str());
                warning_ = "'" + dir + "' is not locked against a second run writing into it: its file system has no locks (" +
                           std::strerror(err) + ")";
                return;
            }
            throw std::runtime_error("cannot lock '" + path + "': " + std::strerror(err));
        }
        if (same_file(fd, path)) {
            fd_ = fd;
            path_ = path;
            break;
        }
        ::close(fd);
        if (round == 1000) throw std::runtime_error("cannot lock '" + path + "': it keeps being removed");
    }
    // The name is for the refusal message only: a full disk that keeps it out does not stop the run.
    const std::string me = holder_text();
    if (::ftruncate(fd_, 0) == 0) {
        [[maybe_unused]] const ssize_t n = ::pwrite(fd_, me.data(), me.size(), 0);
    }
}

void FolderLock::release() noexcept {
    if (fd_ < 0) return;
    // Unlinked while still locked, so no other process can take this file after us and find it
    // gone; and only when `path_` is still ours (a user may have removed it and another run have
    // made its own since).
    if (same_file(fd_, path_)) ::unlink(path_.c_str());
    ::close(fd_);
    fd_ = -1;
    path_.clear();
}

}  // namespace dem
