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

namespace granflow {

// resize() under fit_capacity(); the contents are refilled by the caller.
template <class T>
void refill(std::vector<T>& v, std::size_t n) {
  fit_capacity(v, n);
  v.resize(n);
}

// Heap bytes a vector holds (its capacity, not its size): what the engine's parts report.
template <class T>
std::size_t heap_bytes(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}

}  // namespace granflow
