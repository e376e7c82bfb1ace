// dem::FolderLock, one writer per output folder: a second lock of a folder is refused (in the
// same process and in another), the refusal names the folder and the holder's pid and host, a
// lock left by a killed process is taken over, nested folders lock independently, and the lock
// file goes with the lock.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "dem/io/folder_lock.h"

namespace fs = std::filesystem;
using dem::FolderLock;
using dem::FolderLocked;

namespace {

fs::path scratch(const std::string& name) {
    const fs::path p = fs::temp_directory_path() / ("vppdem_folder_lock_" + std::to_string(::getpid())) / name;
    fs::create_directories(p);
    return p;
}

std::string slurp(const fs::path& p) {
    std::ifstream in(p);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// The message of the FolderLocked that taking dir's lock throws; empty when it is taken.
std::string refusal(const fs::path& dir) {
    try {
        FolderLock again(dir.string());
    } catch (const FolderLocked& e) {
        return e.what();
    }
    return "";
}

std::string host() {
    char h[256] = "";
    ::gethostname(h, sizeof h - 1);
    return h;
}

class FolderLockTest : public ::testing::Test {
protected:
    static void TearDownTestSuite() { fs::remove_all(scratch("").parent_path()); }
};

}  // namespace

TEST_F(FolderLockTest, ASecondLockInTheSameProcessIsRefusedAndTheFileGoesWithTheLock) {
    const fs::path d = scratch("same");
    {
        FolderLock a(d.string());
        ASSERT_TRUE(a.held());
        EXPECT_TRUE(a.warning().empty());
        // The holder's name is in the file, for a refusal to quote.
        EXPECT_NE(slurp(d / FolderLock::kFileName).find("pid " + std::to_string(::getpid()) + "\n"), std::string::npos);
        const std::string why = refusal(d);
        EXPECT_NE(why.find("folder '" + d.string() + "' is in use by another run of this process (pid " +
                           std::to_string(::getpid()) + " on host " + host()),
                  std::string::npos)
            << why;
        // Moved, it stays held; the moved-from object holds nothing and releases nothing.
        FolderLock b(std::move(a));
        EXPECT_FALSE(a.held());
        EXPECT_TRUE(b.held());
        EXPECT_NE(refusal(d), "");
    }
    EXPECT_FALSE(fs::exists(d / FolderLock::kFileName));  // released: no leftover in the folder
    EXPECT_EQ(refusal(d), "");
}

TEST_F(FolderLockTest, NestedFoldersLockIndependently) {
    // A study's folder and its case folders: one process holds both.
    const fs::path study = scratch("study"), one = scratch("study/case_1"), two = scratch("study/case_2");
    FolderLock s(study.string()), a(one.string()), b(two.string());
    EXPECT_TRUE(s.held() && a.held() && b.held());
}

TEST_F(FolderLockTest, AMissingFolderIsAnErrorNamingIt) {
    const std::string missing = (scratch("") / "no_such").string();
    try {
        FolderLock l(missing);
        FAIL() << "locked a missing folder";
    } catch (const FolderLocked&) {
        FAIL() << "a missing folder is no folder in use";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
    }
}

TEST_F(FolderLockTest, AnotherProcessIsRefusedUntilItIsKilledThenItsStaleLockIsTakenOver) {
    const fs::path d = scratch("other");
    int ready[2];
    ASSERT_EQ(::pipe(ready), 0);
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        // The holder: takes the lock, says so, and waits to be killed.
        ::close(ready[0]);
        try {
            FolderLock mine(d.string());
            [[maybe_unused]] const ssize_t n = ::write(ready[1], "1", 1);
            for (;;) ::pause();
        } catch (...) {
            ::_exit(1);
        }
    }
    ::close(ready[1]);
    char c = 0;
    ASSERT_EQ(::read(ready[0], &c, 1), 1) << "the child did not take the lock";
    ::close(ready[0]);

    const std::string why = refusal(d);
    EXPECT_NE(why.find("folder '" + d.string() + "' is in use by another run (pid " + std::to_string(child) +
                       " on host " + host() + ", started "),
              std::string::npos)
        << why;
    EXPECT_NE(why.find("wait for that one to end or stop it, or choose another folder"), std::string::npos) << why;

    // SIGKILL: no destructor runs, the file stays, but the kernel dropped the lock with the process.
    ::kill(child, SIGKILL);
    ::waitpid(child, nullptr, 0);
    ASSERT_TRUE(fs::exists(d / FolderLock::kFileName));
    FolderLock after(d.string());
    EXPECT_TRUE(after.held());
    EXPECT_NE(slurp(d / FolderLock::kFileName).find("pid " + std::to_string(::getpid()) + "\n"), std::string::npos);
}

// Issue 48: a lock file that is a symbolic link was followed, and the file it points to
// truncated and overwritten with the holder's name. It is refused, naming the link, and the
// target is left as it was.
TEST(FolderLockLink, ALockFileThatIsASymbolicLinkIsRefusedAndItsTargetKept) {
    const fs::path d = scratch("link");
    const fs::path target = d / "precious.txt";
    {
        std::ofstream(target) << "the user's data\n";
    }
    const fs::path dir = d / "out";
    fs::create_directories(dir);
    fs::create_symlink(target, dir / ".vppdem.lock");
    std::string message;
    try {
        FolderLock lock(dir.string());
    } catch (const std::exception& e) {
        message = e.what();
    }
    EXPECT_NE(message.find("symbolic link"), std::string::npos) << message;
    EXPECT_NE(message.find(".vppdem.lock"), std::string::npos) << message;
    EXPECT_EQ(slurp(target), "the user's data\n");
    fs::remove_all(d);
}
