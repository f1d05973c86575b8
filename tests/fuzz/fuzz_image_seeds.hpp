// Generated seed images for fuzz_image (no data files in the repository):
// every container OpenCV decodes here, in the layouts load_grey() sorts
// out (1/3/4 channels, 8/16 bit), at odd and tiny sizes.
#ifndef NEGOBS_FUZZ_IMAGE_SEEDS_HPP
#define NEGOBS_FUZZ_IMAGE_SEEDS_HPP

#include <cstdint>
#include <string>
#include <vector>

namespace negobs_fuzz {

// Encoded seed files (contents only), deterministic.
std::vector<std::vector<uint8_t>> image_seeds();

// Writes image_seeds() as DIR/seed_NN; false when DIR cannot be made.
bool write_image_seeds(const std::string &dir);

} // namespace negobs_fuzz

#endif
