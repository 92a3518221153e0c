// stream_file.h — a word stream file (docs/word-format.md: little-endian
// 32-bit words) read whole, for the benches (rtl/bench/cosim.cpp,
// rtl/fpga/bench/top_bench.cpp).  On failure the words so far are empty and
// err names the file and, for a cut-off word, its offset.
#ifndef ALB_STREAM_FILE_H
#define ALB_STREAM_FILE_H

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

inline std::vector<uint32_t> read_stream(const char *path, std::string &err)
{
    std::vector<uint32_t> w;
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        err = std::string(path) + ": cannot open: " + std::strerror(errno);
        return w;
    }
    std::vector<unsigned char> b((std::istreambuf_iterator<char>(in)), {});
    if (in.bad()) {
        err = std::string(path) + ": read error";
        return w;
    }
    if (b.size() % 4) {
        err = std::string(path) + ": offset " + std::to_string(b.size() - b.size() % 4) +
              ": file length is not a whole number of 32-bit words";
        return w;
    }
    for (size_t i = 0; i + 3 < b.size(); i += 4)
        w.push_back((uint32_t)b[i] | (uint32_t)b[i + 1] << 8 | (uint32_t)b[i + 2] << 16 |
                    (uint32_t)b[i + 3] << 24);
    return w;
}

#endif
