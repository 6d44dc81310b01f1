#pragma once
// Checkpoint archives: cereal's binary archives (Debian libcereal-dev) with exact doubles,
// NaN and infinities included. A checkpoint is read back by the same build on the same
// machine kind (the header checks the version), so raw bytes in the machine's order are
// what it holds. Private to the library: included by .cpp files only.
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
void serialize(Archive& ar, ParticleStore& p) {
  ar(raw(p.position), raw(p.velocity), raw(p.angular_velocity), raw(p.radius), raw(p.mass), raw(p.layer));
}

}  // namespace aggpack
