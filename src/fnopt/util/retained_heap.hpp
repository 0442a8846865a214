#pragma once
// Keeps memory that LibTorch frees inside the process for its next tensors.
//
// Every FNO pass allocates and frees tensors of 0.1–10 MB. glibc serves blocks above its mmap
// threshold (128 KB, raised on the fly to the largest freed block) with a fresh mmap, and
// returns the top of the heap to the kernel once more than twice that threshold is free.
// Either way the next pass's tensors land on new pages, which the kernel faults in and zeroes
// again, a large share of fnopt's time per frame (docs/design.md §9). Fixing both thresholds
// keeps those pages mapped and reused.
namespace fnopt {

// Blocks up to this size come from the heap, not from mmap: the upper limit mallopt(3)
// documents for 64-bit systems (an FNO activation of 3 samples × 64 channels at 200² is 31 MB).
constexpr int kHeapBlockLimitBytes = 32 << 20;
// Free memory at the top of the heap beyond this is returned to the kernel.
constexpr int kHeapTrimBytes = 1 << 30;

// Applies both limits to glibc's allocator and returns true; with another C library it does
// nothing and returns false. Call once, before the first large allocation.
bool retain_freed_heap_memory();

}  // namespace fnopt
