// Freed heap given back to the system. glibc keeps what a process frees in
// its arenas, so a large set-up freed before the stepping (the tissue's
// build, the partition, the coupling's assembly) would otherwise stay in the
// run's peak memory beside the stepping's arrays.
#pragma once

#if defined(__GLIBC__)
#include <malloc.h>
#endif

// Under a sanitizer the allocator is the sanitizer's, not glibc's: glibc's
// arenas are never set up, and trimming them from a thread corrupts glibc's
// arena bookkeeping (an assertion at the thread's exit).
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define FIBRODEM_SANITIZER_HEAP 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
#define FIBRODEM_SANITIZER_HEAP 1
#endif
#endif

namespace fibrodem {

// Returns the free pages of every glibc arena to the system; nothing
// elsewhere or under a sanitizer.
inline void give_freed_heap_back() {
#if defined(__GLIBC__) && !defined(FIBRODEM_SANITIZER_HEAP)
  malloc_trim(0);
#endif
}

}  // namespace fibrodem
