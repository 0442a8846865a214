#include <fnopt/util/retained_heap.hpp>

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace fnopt {
namespace {

#if defined(__GLIBC__)
// What an FNO pass does at 64²: a block of several MB freed and allocated again. With the
// limits applied it comes from the heap, not from mmap, and stays mapped after the free.
TEST(RetainedHeap, LargeBlocksComeFromTheHeapAndStayMappedAfterFree) {
  ASSERT_TRUE(retain_freed_heap_memory());
  constexpr size_t kBlock = 8 << 20;
  const struct mallinfo2 before = mallinfo2();
  auto* block = static_cast<char*>(std::malloc(kBlock));
  ASSERT_NE(block, nullptr);
  std::memset(block, 1, kBlock);
  const struct mallinfo2 allocated = mallinfo2();
  EXPECT_EQ(allocated.hblkhd, before.hblkhd) << "the block was served by mmap";
  EXPECT_GE(allocated.arena, before.arena + kBlock);
  std::free(block);
  const struct mallinfo2 freed = mallinfo2();
  EXPECT_GE(freed.arena, before.arena + kBlock) << "the heap was trimmed after the free";
  EXPECT_GE(freed.fordblks, kBlock);
}

// Blocks beyond the limit still go to mmap, so a huge grid does not pin its memory forever.
TEST(RetainedHeap, BlocksBeyondTheLimitStillUseMmap) {
  ASSERT_TRUE(retain_freed_heap_memory());
  const struct mallinfo2 before = mallinfo2();
  void* block = std::malloc(size_t{2} * kHeapBlockLimitBytes);
  ASSERT_NE(block, nullptr);
  EXPECT_GE(mallinfo2().hblkhd, before.hblkhd + size_t{2} * kHeapBlockLimitBytes);
  std::free(block);
}
#else
TEST(RetainedHeap, DoesNothingWithoutGlibc) { EXPECT_FALSE(retain_freed_heap_memory()); }
#endif

}  // namespace
}  // namespace fnopt
