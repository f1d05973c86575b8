// Driver of fuzz_image without libFuzzer (a plain test, also under the
// sanitizers): runs the files named on the command line, or else every
// generated seed image, each truncated at a few lengths and with single
// bit flips at a spread of positions, deterministically.
#include <cstdint>
#include <cstdio>
#include <vector>

#include "fuzz_image_seeds.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int main(int argc, char **argv)
{
    if (argc > 1) {
        for (int i = 1; i < argc; i++) {
            FILE *f = std::fopen(argv[i], "rb");
            if (f == nullptr) {
                std::fprintf(stderr, "cannot open %s\n", argv[i]);
                return 1;
            }
            std::vector<uint8_t> buf;
            int c;
            while ((c = std::fgetc(f)) != EOF) {
                buf.push_back(static_cast<uint8_t>(c));
            }
            std::fclose(f);
            LLVMFuzzerTestOneInput(buf.data(), buf.size());
        }
        std::printf("%d file(s) ran cleanly\n", argc - 1);
        return 0;
    }
    std::vector<std::vector<uint8_t>> seeds = negobs_fuzz::image_seeds();
    unsigned runs = 0;
    for (const std::vector<uint8_t> &s : seeds) {
        LLVMFuzzerTestOneInput(s.data(), s.size());
        runs++;
        // Truncated files: header only, half, all but the last byte.
        const size_t cuts[] = {0, 8, 20, s.size() / 2, s.size() - 1};
        for (size_t cut : cuts) {
            if (cut < s.size()) {
                LLVMFuzzerTestOneInput(s.data(), cut);
                runs++;
            }
        }
        // Corrupt files: one bit flipped, in the header and beyond.
        for (size_t k = 0; k < 24; k++) {
            std::vector<uint8_t> m = s;
            size_t pos = (k * 7919u) % m.size();
            m[pos] = static_cast<uint8_t>(m[pos] ^ (1u << (k % 8u)));
            LLVMFuzzerTestOneInput(m.data(), m.size());
            runs++;
        }
    }
    std::printf("%zu seed images, %u inputs ran cleanly\n", seeds.size(),
                runs);
    return seeds.size() >= 10 ? 0 : 1;
}
