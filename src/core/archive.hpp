#pragma once
// Checkpoint archives: cereal's binary layout (Debian libcereal-dev) with exact doubles,
// NaN and infinities included. A checkpoint is read back by the same build on the same
// machine kind (the header checks the version), so raw bytes in the machine's order are
// what it holds. Written by cereal's BinaryOutputArchive, read by CheckedInputArchive below.
// Private to the library: included by .cpp files only.
#include <algorithm>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include <cereal/archives/binary.hpp>
#include <cereal/types/deque.hpp>
#include <cereal/types/map.hpp>
#include <cereal/types/optional.hpp>
#include <cereal/types/string.hpp>
#include <cereal/types/vector.hpp>

#include "aggpack/core/container.hpp"
#include "aggpack/core/particle_store.hpp"
#include "aggpack/core/vec3.hpp"

namespace aggpack {

// Reads what cereal's BinaryOutputArchive wrote, from bytes in memory, without trusting them:
// a read past the end, a length (of a string, a vector, a map) longer than the bytes left, or
// a flag neither 0 nor 1 throws cereal::Exception, before anything is allocated for it.
// cereal's BinaryInputArchive would allocate whatever a damaged length says, and load any
// byte into a bool.
class CheckedInputArchive : public cereal::InputArchive<CheckedInputArchive, cereal::AllowEmptyClassElision> {
 public:
  explicit CheckedInputArchive(std::string_view bytes) : InputArchive(this), bytes_(bytes) {}

  void load_binary(void* data, std::size_t size) {
    if (size > left()) throw cereal::Exception(fmt_wanted(size));
    if (size > 0) std::memcpy(data, bytes_.data() + at_, size);
    at_ += size;
  }
  // A count of `count` items of at least `item_bytes` bytes each must fit in the bytes left.
  void check_count(std::uint64_t count, std::size_t item_bytes) const {
    if (count > left() / std::max<std::size_t>(1, item_bytes))
      throw cereal::Exception(fmt_wanted(count) + " items (a damaged length)");
  }
  [[nodiscard]] std::size_t left() const { return bytes_.size() - at_; }
  [[nodiscard]] std::size_t position() const { return at_; }

 private:
  [[nodiscard]] std::string fmt_wanted(std::uint64_t size) const {
    return std::to_string(size) + " wanted at byte " + std::to_string(at_) + " of " + std::to_string(bytes_.size());
  }
  std::string_view bytes_;
  std::size_t at_ = 0;
};

template <class T>
std::enable_if_t<std::is_arithmetic_v<T>> CEREAL_LOAD_FUNCTION_NAME(CheckedInputArchive& ar, T& value) {
  ar.load_binary(std::addressof(value), sizeof value);
}
inline void CEREAL_LOAD_FUNCTION_NAME(CheckedInputArchive& ar, bool& value) {
  unsigned char byte = 0;  // any other byte in a bool would be undefined behaviour
  ar.load_binary(&byte, 1);
  if (byte > 1) throw cereal::Exception("a flag neither 0 nor 1");
  value = byte != 0;
}
template <class T>
void CEREAL_LOAD_FUNCTION_NAME(CheckedInputArchive& ar, cereal::NameValuePair<T>& pair) {
  ar(pair.value);
}
template <class T>
void CEREAL_LOAD_FUNCTION_NAME(CheckedInputArchive& ar, cereal::SizeTag<T>& tag) {
  ar(tag.size);
  ar.check_count(tag.size, 1);  // every item of a string, vector or map takes a byte at least
}
template <class T>
void CEREAL_LOAD_FUNCTION_NAME(CheckedInputArchive& ar, cereal::BinaryData<T>& data) {
  ar.load_binary(data.data, static_cast<std::size_t>(data.size));
}

// A vector of plain values (Vec3, packed records) as one block of bytes: cereal would
// otherwise write it element by element.
template <class T>
struct RawVector {
  static_assert(std::is_trivially_copyable_v<T>);
  std::vector<T>& values;
  template <class Archive>
  void save(Archive& ar) const {
    ar(static_cast<std::uint64_t>(values.size()));
    ar(cereal::binary_data(values.data(), values.size() * sizeof(T)));
  }
  template <class Archive>
  void load(Archive& ar) {
    std::uint64_t size = 0;
    ar(size);
    ar.check_count(size, sizeof(T));
    values.resize(size);
    ar(cereal::binary_data(values.data(), values.size() * sizeof(T)));
  }
};
template <class T>
RawVector<T> raw(std::vector<T>& values) {
  return {values};
}
template <class T>
RawVector<T> raw(const std::vector<T>& values) {  // saving only
  return {const_cast<std::vector<T>&>(values)};
}

// A plain value (a random stream's state, a container) as its bytes.
template <class T>
auto raw_value(T& value) {
  static_assert(std::is_trivially_copyable_v<std::remove_const_t<T>>);
  return cereal::binary_data(const_cast<std::remove_const_t<T>*>(&value), sizeof(T));
}

template <class Archive>
void serialize(Archive& ar, RigidBodies& b) {
  ar(raw(b.first_member), raw(b.member_count), raw(b.position), raw(b.orientation), raw(b.velocity),
     raw(b.angular_velocity), raw(b.mass), raw(b.volume), raw(b.principal_inertia), raw(b.shape));
}

// A store's arrays as they are; whoever restores one checks them against its run (a damaged
// file can make arrays of any lengths and indices of any values).
template <class Archive>
void serialize(Archive& ar, ParticleStore& p) {
  ar(raw(p.position), raw(p.velocity), raw(p.angular_velocity), raw(p.radius), raw(p.mass), raw(p.layer),
     raw(p.material), raw(p.body), raw(p.body_offset), p.bodies);
}

}  // namespace aggpack

// cereal pairs each input archive with its output archive (for its minimal-save checks).
namespace cereal::traits::detail {
template <>
struct get_output_from_input<aggpack::CheckedInputArchive> {
  using type = cereal::BinaryOutputArchive;
};
}  // namespace cereal::traits::detail
