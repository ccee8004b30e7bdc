// How many times the program's operator new has run so far, on every thread: the alloc test
// program replaces operator new with a counting one (tests/alloc/counting_allocator.cpp).
// A test compares two counts around work no other thread does meanwhile.
#pragma once

#include <atomic>
#include <cstdint>

namespace tiltgate::test {

std::uint64_t allocations_so_far();

}  // namespace tiltgate::test
