// GzipWriter / GzipReader (models/plumbing/gzip_stream.h): what is written comes back byte for byte, through
// zlib's own reader as well as ours; the same text gives the same bytes (no time in the header);
// a plain file reads as it is; a missing file reads as empty; and the compressed rows are a small
// fraction of the plain ones (the point of interrupts.csv.gz).
#include "models/plumbing/gzip_stream.h"
#include "tests/support/files.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace fs = std::filesystem;

namespace {

// Rows shaped like interrupts.csv's: 200 000 of them, over 10 MB plain.
std::string csv_like_rows() {
    std::ostringstream s;
    s << "source,level,vector,ir_rise_us\n";
    for (unsigned i = 0; i < 200000; ++i)
        s << "rs232_" << i % 3 << "," << i % 3 << "," << 0x40 + i % 3 << "," << i * 382.125 << ","
          << i * 382.125 + 21.5 << ",F03" << i % 7 << "A\n";
    return s.str();
}

std::string gzip_of(const std::string& text) {
    std::ostringstream sink;
    rcsim::GzipWriter gz(sink);
    gz << text;
    gz.finish();
    return sink.str();
}

fs::path temp_file(const std::string& name, const std::string& bytes) {
    const fs::path p = rcsim::test::scratch_dir() / name;
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
}

std::string read_all(std::istream& in) {
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

} // namespace

TEST(GzipStream, WhatIsWrittenReadsBackWholeThroughZlibAndOurReader) {
    const std::string text = csv_like_rows();
    const std::string gz = gzip_of(text);
    ASSERT_GE(gz.size(), 2u);
    EXPECT_EQ(static_cast<unsigned char>(gz[0]), 0x1F); // RFC 1952 ID1, ID2
    EXPECT_EQ(static_cast<unsigned char>(gz[1]), 0x8B);
    const fs::path p = temp_file("rows.csv.gz", gz);
    // zlib's reader, independent of GzipReader's buffering.
    gzFile f = gzopen(p.c_str(), "rb");
    ASSERT_NE(f, nullptr);
    std::string via_zlib(text.size() + 1, '\0');
    const int n = gzread(f, via_zlib.data(), static_cast<unsigned>(via_zlib.size()));
    gzclose(f);
    ASSERT_EQ(n, static_cast<int>(text.size()));
    via_zlib.resize(static_cast<std::size_t>(n));
    EXPECT_EQ(via_zlib, text);
    rcsim::GzipReader in(p);
    EXPECT_EQ(read_all(in), text);
}

TEST(GzipStream, TheSameTextGivesTheSameBytes) {
    const std::string text = csv_like_rows();
    EXPECT_EQ(gzip_of(text), gzip_of(text));
    // The header's MTIME (bytes 4..7) is 0: nothing of the host's clock.
    const std::string gz = gzip_of(text);
    EXPECT_EQ(gz.substr(4, 4), std::string(4, '\0'));
}

TEST(GzipStream, RowsCompressToAFractionOfTheirSize) {
    const std::string text = csv_like_rows();
    EXPECT_LT(gzip_of(text).size() * 4, text.size());
}

TEST(GzipStream, EmptyInputIsAValidEmptyMember) {
    const fs::path p = temp_file("empty.gz", gzip_of(""));
    rcsim::GzipReader in(p);
    EXPECT_EQ(read_all(in), "");
    EXPECT_GT(fs::file_size(p), 0u);
}

TEST(GzipStream, APlainFileReadsAsItIs) {
    const fs::path p = temp_file("plain.csv", "a,b\n1,2\n");
    rcsim::GzipReader in(p);
    std::string line;
    ASSERT_TRUE(std::getline(in, line));
    EXPECT_EQ(line, "a,b");
    ASSERT_TRUE(std::getline(in, line));
    EXPECT_EQ(line, "1,2");
    EXPECT_FALSE(std::getline(in, line));
}

TEST(GzipStream, AMissingFileReadsAsEmpty) {
    rcsim::GzipReader in(rcsim::test::scratch_dir() / "no-such-file.gz");
    std::string line;
    EXPECT_FALSE(std::getline(in, line));
}
