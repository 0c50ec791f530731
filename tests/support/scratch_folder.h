/// \file scratch_folder.h
/// A folder of this test process's own for the files a test writes (test binaries run in
/// parallel, so the process id is in its name), and a fixture that owns one per test.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <utility>

namespace crex::testing {

/// Made when first asked for; the caller removes it.
inline std::filesystem::path scratch_folder(const std::string& prefix) {
    std::filesystem::path dir = std::filesystem::temp_directory_path() / (prefix + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    return dir;
}

/// A fixture whose tests write into `dir_`: made before each test, removed after it.
class ScratchFolderTest : public ::testing::Test {
protected:
    explicit ScratchFolderTest(std::string prefix) : prefix_(std::move(prefix)) {}
    void SetUp() override { dir_ = scratch_folder(prefix_); }
    void TearDown() override { std::filesystem::remove_all(dir_); }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    std::filesystem::path dir_;

private:
    std::string prefix_;
};

}  // namespace crex::testing
