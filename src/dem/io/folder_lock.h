// One writer per output folder: a lock on DIR/.vppdem.lock held for the life of a run, so that
// a second process writing into DIR (a second `--overwrite` run, a second sweep of a study)
// refuses before it deletes or writes anything, instead of removing the files of the run in
// progress under it.
//
// The lock is flock(LOCK_EX | LOCK_NB) on the lock file. The kernel drops it when the holding
// process ends, however it ends (SIGKILL, a crash, a node's reboot): a lock file left behind by a
// killed run is stale by construction and the next run simply takes it again, with no pid to
// test for life and no age to guess. fcntl(F_SETLK) record locks were the alternative; they
// belong to the process, so a second lock of one folder in the same process would succeed
// silently and closing any descriptor of the file would drop the lock. flock locks belong to
// the open file: two FolderLocks of one folder conflict even in one process (two Python Dampers
// writing one folder are refused too), while nested folders (a study and its case folders) are
// different files and are locked independently.
//
// NFS: Linux (2.6.12 and later) maps flock onto NFS byte-range locks, which hold between the
// clients when the server runs its lock manager; other systems may lock only on the local
// machine, and some file systems (NFS without a lock manager, some FUSE and SMB mounts) have no
// locks at all. There FolderLock holds nothing and says why (warning()): the run goes on as it
// did before folders were locked, rather than refusing to run on a cluster's shared disk.
//
// The holder writes its pid, host, start time and command line into the file, so a refusal can
// name it. The file is removed when the lock is released (a run's end, or an error that stops
// it); a killed run leaves it behind, harmless.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>

namespace dem {

// Thrown when another holder has the folder's lock; the message names the folder and the holder
// (pid, host, start, command) as far as the lock file tells.
struct FolderLocked : std::runtime_error {
    using std::runtime_error::runtime_error;
};

class FolderLock {
public:
    static constexpr const char* kFileName = ".vppdem.lock";

    FolderLock() = default;  // holds nothing
    // Takes DIR's lock; DIR must exist. Throws FolderLocked when it is held (by another process,
    // or by another FolderLock of this one), std::runtime_error naming the path when DIR is no
    // folder or the lock file cannot be created.
    explicit FolderLock(const std::string& dir);
    ~FolderLock() { release(); }
    FolderLock(FolderLock&& o) noexcept { swap(o); }
    FolderLock& operator=(FolderLock&& o) noexcept {
        FolderLock(std::move(o)).swap(*this);
        return *this;
    }
    FolderLock(const FolderLock&) = delete;
    FolderLock& operator=(const FolderLock&) = delete;

    bool held() const { return fd_ >= 0; }
    // Why nothing is held although DIR was given: the file system has no locks (empty otherwise).
    const std::string& warning() const { return warning_; }
    // Removes the lock file and drops the lock (the destructor does); then holds nothing.
    void release() noexcept;

private:
    void swap(FolderLock& o) noexcept {
        std::swap(fd_, o.fd_);
        path_.swap(o.path_);
        warning_.swap(o.warning_);
    }
    int fd_ = -1;
    std::string path_;  // DIR/.vppdem.lock
    std::string warning_;
};

}  // namespace dem
