// The one check of numbers users give (base/number_range.h) and the bounded reader of input
// files (base/input_file.h).
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "base/input_file.h"
#include "base/number_range.h"
#include "tests/support/scratch_folder.h"

namespace crex {
namespace {

namespace fs = std::filesystem;

TEST(NumberRange, NamesNanAndInfinityWithTheRange) {
    const NumberRange unit{0, 1, false};
    EXPECT_EQ(number_range_error(0.5, unit), "");
    EXPECT_EQ(number_range_error(std::nan(""), unit), "nan is not a number: expected a number from 0 to 1");
    EXPECT_EQ(number_range_error(INFINITY, unit), "inf is infinite: expected a number from 0 to 1");
    EXPECT_EQ(number_range_error(-INFINITY, unit), "-inf is infinite: expected a number from 0 to 1");
    EXPECT_EQ(number_range_error(2, unit), "2 is out of range: expected a number from 0 to 1");
    EXPECT_EQ(number_range_error(1.5, {1, 1 << 20, true}), "1.5 is not a whole number: expected a whole number from 1 to 1048576");
    EXPECT_EQ(describe({1e-6, 1e30, false}), "a number from 1e-6 to 1e30");
}

TEST(NumberRange, ReadsTextWholeAndWholeNumbersExactly) {
    const NumberRange seed{0, 9007199254740992.0, true};
    EXPECT_EQ(number_text_error("9007199254740992", seed), "");
    // As a double this is 9007199254740992: the digits are compared, not the double.
    EXPECT_EQ(number_text_error("9007199254740993", seed),
              "'9007199254740993' is out of range: expected a whole number from 0 to 9007199254740992");
    EXPECT_NE(number_text_error("99999999999999999999999", seed), "");  // past uint64
    EXPECT_NE(number_text_error("-1", seed), "");
    EXPECT_NE(number_text_error("1e3", seed), "");
    EXPECT_NE(number_text_error("0x10", seed), "");
    EXPECT_NE(number_text_error("1 ", {0, 10, false}), "");  // nothing trailing
    EXPECT_NE(number_text_error(" 1", {0, 10, false}), "");
    EXPECT_NE(number_text_error("", {0, 10, false}), "");
    EXPECT_EQ(number_text_error("1e-3", {0, 1, false}), "");
    EXPECT_EQ(number_text_error("nan", {0, 1, false}), "'nan' is not a number: expected a number from 0 to 1");
    EXPECT_EQ(number_text_error("-inf", {0, 1, false}), "'-inf' is infinite: expected a number from 0 to 1");
    EXPECT_EQ(number_text_error("\x1b[2J", {0, 1, false}), "'?[2J' is not a number: expected a number from 0 to 1");
}

class InputFile : public testing::ScratchFolderTest {
protected:
    InputFile() : ScratchFolderTest("crex_input_file_") {}
};

TEST_F(InputFile, ReadsARegularFileWhole) {
    std::ofstream(path("a.txt")) << "hello";
    std::string error;
    auto text = read_input_file(path("a.txt"), error);
    ASSERT_TRUE(text) << error;
    EXPECT_EQ(*text, "hello");
    EXPECT_EQ(check_input_file(path("a.txt")), "");
}

TEST_F(InputFile, RefusesWhatIsNotAFileWithoutBlocking) {
    ASSERT_EQ(::mkfifo(path("f").c_str(), 0600), 0);
    std::string error;
    EXPECT_FALSE(read_input_file(path("f"), error));  // would block for ever if it opened the FIFO for reading
    EXPECT_EQ(error, "cannot read '" + path("f") + "': it is a named pipe (FIFO), not a file; give a file (or '-' for standard input "
                                                   "where a command reads it)");
    EXPECT_FALSE(read_input_file("/dev/zero", error));
    EXPECT_NE(error.find("it is a character device, not a file"), std::string::npos) << error;
    EXPECT_FALSE(read_input_file(dir_.string(), error));
    EXPECT_EQ(error, "cannot read '" + dir_.string() + "': it is a directory");
    EXPECT_FALSE(read_input_file(path("missing"), error));
    EXPECT_EQ(error, "cannot read '" + path("missing") + "': No such file or directory");
    EXPECT_NE(check_input_file("/dev/zero"), "");
}

TEST_F(InputFile, RefusesMoreThanItsLimit) {
    std::ofstream(path("b.txt")) << std::string(2000, 'x');
    std::string error;
    EXPECT_FALSE(read_input_file(path("b.txt"), error, 1024));
    EXPECT_EQ(error, "cannot read '" + path("b.txt") + "': it is 1.95 KiB, more than the 1 KiB crex reads from one input");
    EXPECT_TRUE(read_input_file(path("b.txt"), error, 2000));
    EXPECT_EQ(byte_size_text(64.0 * (1 << 20)), "64 MiB");
}

}  // namespace
}  // namespace crex
