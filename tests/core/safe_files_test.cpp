// The safe-file helpers every writer of pxh uses: UTF-8 validation (run.json records paths and
// text) and new files that never follow links or replace a file.
#include "harness/core/safe_files.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "harness/core/error.h"
#include "tests/cli_util.h"

namespace {

namespace fs = std::filesystem;

TEST(SafeFiles, Utf8Validation) {
    using pxh::invalid_utf8_at;
    const size_t none = std::string::npos;
    EXPECT_EQ(invalid_utf8_at(""), none);
    EXPECT_EQ(invalid_utf8_at("plain ascii\n\t"), none);
    EXPECT_EQ(invalid_utf8_at("\xc3\xa9\xe2\x82\xac\xf0\x9d\x84\x9e\xf4\x8f\xbf\xbf"), none);
    EXPECT_EQ(invalid_utf8_at("ab\xe9"), 2u);            // Latin-1
    EXPECT_EQ(invalid_utf8_at("a\xc0\x80"), 1u);         // overlong NUL
    EXPECT_EQ(invalid_utf8_at("\xe0\x80\xaf"), 0u);      // overlong '/'
    EXPECT_EQ(invalid_utf8_at("x\xed\xa0\x80"), 1u);     // a surrogate
    EXPECT_EQ(invalid_utf8_at("\xf4\x90\x80\x80"), 0u);  // past U+10FFFF
    EXPECT_EQ(invalid_utf8_at("abc\xe2\x82"), 3u);       // cut short
    EXPECT_EQ(invalid_utf8_at("\x80"), 0u);              // a lone continuation byte
    EXPECT_EQ(invalid_utf8_at("\xc3\xa9\xc3\x28"), 2u);  // a bad continuation
    EXPECT_EQ(pxh::utf8_problem("a\nbc\nde\xff"), "line 3, column 3: byte 0xFF is not UTF-8");
}

TEST(SafeFiles, NewFilesNeverFollowLinksOrReplaceFiles) {
    const fs::path d = fs::temp_directory_path() / ("pxh_safe_" + std::to_string(getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    std::ofstream(d / "theirs.txt") << "theirs";
    fs::create_symlink(d / "theirs.txt", d / "link");
    fs::create_symlink(d / "nowhere", d / "dangling");
    for (const char* name : {"theirs.txt", "link", "dangling"}) {
        try {
            pxh::create_new_file(d / name, "ours");
            ADD_FAILURE() << name << " was written";
        } catch (const std::runtime_error& e) {
            EXPECT_NE(std::string(e.what()).find(": cannot create: "), std::string::npos);
        }
    }
    EXPECT_FALSE(fs::exists(d / "nowhere"));  // not created through the dangling link
    std::ifstream f(d / "theirs.txt");
    std::string text;
    f >> text;
    EXPECT_EQ(text, "theirs");
    pxh::create_new_file(d / "new.txt", "ours");
    EXPECT_EQ(fs::file_size(d / "new.txt"), 4u);
    // Folders: a link to a folder is not taken for one; unique folders never collide.
    fs::create_directories(d / "real");
    fs::create_directory_symlink(d / "real", d / "maps");
    pxh::make_own_folder(d / "real");  // exists, a real folder: fine
    EXPECT_THROW(pxh::make_own_folder(d / "maps"), std::runtime_error);
    std::set<std::string> made;
    for (int k = 0; k < 20; ++k) made.insert(pxh::make_unique_folder((d / "x.partial-1").string()));
    EXPECT_EQ(made.size(), 20u);
    fs::remove_all(d);
}

// A copy is a new file like any other (never over a file or through a link) of the source's
// bytes, and only a regular file is copied (a link is refused, not followed).
TEST(SafeFiles, CopiesAreNewFilesOfRegularFiles) {
    const fs::path d = fs::temp_directory_path() / ("pxh_copy_" + std::to_string(getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    const std::string bytes("a\0b\nc", 5);
    pxh::create_new_file(d / "src.bin", bytes);
    pxh::copy_to_new_file(d / "src.bin", d / "copy.bin");
    std::ifstream f(d / "copy.bin", std::ios::binary);
    const std::string got((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    EXPECT_EQ(got, bytes);
    EXPECT_THROW(pxh::copy_to_new_file(d / "src.bin", d / "copy.bin"), std::runtime_error);
    fs::create_symlink(d / "src.bin", d / "link");
    EXPECT_THROW(pxh::copy_to_new_file(d / "link", d / "via_link.bin"), std::runtime_error);
    EXPECT_FALSE(fs::exists(d / "via_link.bin"));
    EXPECT_THROW(pxh::copy_to_new_file(d / "missing", d / "m.bin"), std::runtime_error);
    pxh::sync_tree(d);  // every file and folder, the link skipped
    fs::remove_all(d);
}

}  // namespace
