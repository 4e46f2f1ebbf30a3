// AtomicFile: a file is replaced whole or not at all, nothing is written through a planted
// symlink, devices are written in place with every write checked, and a FIFO nobody reads is
// refused instead of blocking.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "output/atomic_file.h"

namespace veach {
namespace {

namespace fs = std::filesystem;

class AtomicFileTest : public ::testing::Test {
protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() / ("veach_atomic_" + std::to_string(::getpid()) + "_" +
                                             ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(m_dir);
        fs::create_directories(m_dir);
    }
    void TearDown() override { fs::remove_all(m_dir); }

    static std::string read(const fs::path& p) {
        std::ifstream f(p, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(f), {});
    }
    static void write(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }
    // Everything in the folder but `keep`: temporaries left behind show up here.
    size_t entries() const { return static_cast<size_t>(std::distance(fs::directory_iterator(m_dir), {})); }

    fs::path m_dir;
};

TEST_F(AtomicFileTest, ReplacesTheFileWholeAndLeavesNoTemporary) {
    const fs::path target = m_dir / "a.bin";
    write(target, "old");
    write_file_atomically(target.string(), "new contents", 12);
    EXPECT_EQ(read(target), "new contents");
    EXPECT_EQ(entries(), 1u);
}

TEST_F(AtomicFileTest, UncommittedFileLeavesTheOldOneAndNoTemporary) {
    const fs::path target = m_dir / "a.bin";
    write(target, "old");
    {
        AtomicFile f(target.string());
        f.write("half", 4);
    }  // destroyed without commit: a failed render
    EXPECT_EQ(read(target), "old");
    EXPECT_EQ(entries(), 1u);
}

TEST_F(AtomicFileTest, ReplacesASymlinkAtTheTargetInsteadOfWritingThroughIt) {
    const fs::path victim = m_dir / "victim";
    write(victim, "precious");
    fs::create_symlink(victim, m_dir / "out.json");
    write_file_atomically((m_dir / "out.json").string(), "{}", 2);
    EXPECT_EQ(read(victim), "precious");
    EXPECT_FALSE(fs::is_symlink(m_dir / "out.json"));
    EXPECT_EQ(read(m_dir / "out.json"), "{}");
}

TEST_F(AtomicFileTest, PlantedTemporaryNamesAreNeverWrittenThrough) {
    // The names the writers used before (pid-based, or NAME.tmp) planted as symlinks to a victim.
    const fs::path victim = m_dir / "victim";
    write(victim, "precious");
    const std::string pid = std::to_string(::getpid());
    for (const std::string& name : {std::string("out.png.tmp"), ".out.tmp-" + pid + "-0.png", ".out.png.tmp-" + pid})
        fs::create_symlink(victim, m_dir / name);
    write_file_atomically((m_dir / "out.png").string(), "png", 3);
    EXPECT_EQ(read(victim), "precious");
    EXPECT_EQ(read(m_dir / "out.png"), "png");
}

TEST_F(AtomicFileTest, AFullDeviceFailsTheWriteWithItsReason) {
    try {
        AtomicFile f("/dev/full");
        f.write("x", 1);
        f.commit();
        FAIL() << "writing /dev/full succeeded";
    } catch (const OutputError& e) {
        EXPECT_NE(std::string(e.what()).find("/dev/full: write failed (No space left on device)"), std::string::npos)
            << e.what();
    }
}

TEST_F(AtomicFileTest, ACharacterDeviceIsWrittenInPlace) {
    write_file_atomically("/dev/null", "discarded", 9);  // no rename over /dev/null
    struct stat st {};
    ASSERT_EQ(::stat("/dev/null", &st), 0);
    EXPECT_TRUE(S_ISCHR(st.st_mode));
}

TEST_F(AtomicFileTest, AFifoWithoutAReaderIsRefusedInsteadOfBlocking) {
    const fs::path fifo = m_dir / "pipe";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    EXPECT_THROW(AtomicFile f(fifo.string()), OutputError);
}

TEST_F(AtomicFileTest, FoldersAndMissingFoldersAreRefused) {
    EXPECT_THROW(write_file_atomically(m_dir.string(), "x", 1), OutputError);
    EXPECT_THROW(write_file_atomically((m_dir / "none" / "a.bin").string(), "x", 1), OutputError);
    EXPECT_THROW(write_file_atomically("", "x", 1), OutputError);
    EXPECT_EQ(entries(), 0u);
}

}  // namespace
}  // namespace veach
