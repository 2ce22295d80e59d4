#pragma once
// Capacity policy for the engine's per-contact arrays, which are refilled every step.
#include <cstddef>
#include <vector>

namespace granflow {

// Makes room for n elements, dropping the contents if it reallocates: grows by an eighth
// rather than doubling, and shrinks once the capacity exceeds four times the need, so that
// memory follows the use (a start-up transient included) instead of its high-water mark.
template <class T>
void fit_capacity(std::vector<T>& v, std::size_t n) {
  if (n > v.capacity() || v.capacity() > 4 * n + 1024) {
    std::vector<T> fresh;
    fresh.reserve(n + n / 8);
    v.swap(fresh);
  }
}

}  // namespace granflow
