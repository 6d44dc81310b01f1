#pragma once
// XXH64 (seed 0), the 64-bit checksum of a checkpoint's sections: it sees any damage to the
// bytes (a flipped bit, a byte changed, a length cut) but for a chance of 2^-64, at several
// GB/s, and takes its bytes in pieces of any size (a section is streamed into its file).
// Private to the library: included by .cpp files only.
#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string_view>

namespace aggpack {

class Checksum {
 public:
  void add(std::string_view bytes) {
    const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
    std::size_t n = bytes.size();
    total_ += n;
    if (pending_ > 0) {  // complete the stripe left over from the last piece
      const std::size_t take = std::min(n, kStripe - pending_);
      std::memcpy(stripe_.data() + pending_, p, take);
      pending_ += take, p += take, n -= take;
      if (pending_ < kStripe) return;
      consume(stripe_.data());
      pending_ = 0;
    }
    for (; n >= kStripe; p += kStripe, n -= kStripe) consume(p);
    std::memcpy(stripe_.data(), p, n);
    pending_ = n;
  }

  [[nodiscard]] std::uint64_t value() const {
    std::uint64_t h = total_ >= kStripe ? merged() : kP5;
    h += total_;
    const unsigned char* p = stripe_.data();
    std::size_t n = pending_;
    for (; n >= 8; p += 8, n -= 8) h = std::rotl(h ^ round(0, read<std::uint64_t>(p)), 27) * kP1 + kP4;
    if (n >= 4) h = std::rotl(h ^ read<std::uint32_t>(p) * kP1, 23) * kP2 + kP3, p += 4, n -= 4;
    for (; n > 0; ++p, --n) h = std::rotl(h ^ *p * kP5, 11) * kP1;
    h = (h ^ (h >> 33)) * kP2;
    h = (h ^ (h >> 29)) * kP3;
    return h ^ (h >> 32);
  }

 private:
  static constexpr std::uint64_t kP1 = 0x9E3779B185EBCA87ull, kP2 = 0xC2B2AE3D27D4EB4Full,
                                 kP3 = 0x165667B19E3779F9ull, kP4 = 0x85EBCA77C2B2AE63ull,
                                 kP5 = 0x27D4EB2F165667C5ull;
  static constexpr std::size_t kStripe = 32;

  template <class T>
  static T read(const unsigned char* p) {  // little-endian, as XXH64 reads (the machines aggpack runs on)
    T v;
    std::memcpy(&v, p, sizeof v);
    return v;
  }
  static std::uint64_t round(std::uint64_t acc, std::uint64_t input) { return std::rotl(acc + input * kP2, 31) * kP1; }
  void consume(const unsigned char* p) {
    for (std::size_t k = 0; k < 4; ++k) lane_[k] = round(lane_[k], read<std::uint64_t>(p + 8 * k));
  }
  [[nodiscard]] std::uint64_t merged() const {
    std::uint64_t h = std::rotl(lane_[0], 1) + std::rotl(lane_[1], 7) + std::rotl(lane_[2], 12) + std::rotl(lane_[3], 18);
    for (const std::uint64_t v : lane_) h = (h ^ round(0, v)) * kP1 + kP4;
    return h;
  }

  std::array<std::uint64_t, 4> lane_{kP1 + kP2, kP2, 0, 0 - kP1};
  std::array<unsigned char, kStripe> stripe_{};
  std::size_t pending_ = 0;
  std::uint64_t total_ = 0;
};

[[nodiscard]] inline std::uint64_t checksum(std::string_view bytes) {
  Checksum c;
  c.add(bytes);
  return c.value();
}

}  // namespace aggpack
