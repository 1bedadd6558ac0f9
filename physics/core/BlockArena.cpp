#include "physics/core/BlockArena.h"

#include <algorithm>
#include <cstdint>

namespace strata {

BlockPool::~BlockPool() {
  for (Block* block = free_; block != nullptr;) {
    Block* next = block->next;
    std::byte* const memory = block->memory;
    block->~Block();
    ::operator delete[](memory, std::align_val_t(kAlignment));
    block = next;
  }
}

BlockPool::Block* BlockPool::Take(std::size_t bytes) {
  {
    std::lock_guard lock(mutex_);
    // First fit; almost every block has the standard size, so this is usually the first one.
    for (Block** link = &free_; *link != nullptr; link = &(*link)->next) {
      if ((*link)->size < bytes) continue;
      Block* block = *link;
      *link = block->next;
      block->next = nullptr;
      return block;
    }
  }
  return MakeBlock(std::max(bytes, block_bytes_));
}

BlockPool::Block* BlockPool::MakeBlock(std::size_t size) {
  // Every block has room for the largest colour offset, so each takes the same bytes whatever its colour.
  constexpr std::size_t kColourRoom =
      (kColours - 1) * kAlignment;  // the colours are every 64 bytes of a page
  const std::size_t allocated = kHeaderBytes + size + kColourRoom;
  auto* memory = static_cast<std::byte*>(::operator new[](allocated, std::align_val_t(kAlignment)));
  std::lock_guard lock(mutex_);
  // The block's page offset is its colour whatever page offset the allocation began at.
  const std::size_t colour = next_colour_++ % kColours * kColourStride % 4096;
  const std::size_t shift = (colour + 4096 - reinterpret_cast<std::uintptr_t>(memory) % 4096) % 4096;
  Block* block = new (memory + shift) Block;
  block->size = size;
  block->memory = memory;
  bytes_reserved_ += allocated;
  if (size == block_bytes_) standard_blocks_.fetch_add(1, std::memory_order_release);
  return block;
}

void BlockPool::EnsureBlocks(std::size_t blocks) {
  while (standard_blocks_.load(std::memory_order_acquire) < blocks) Give(MakeBlock(block_bytes_));
}

void BlockPool::Give(Block* chain) {
  if (chain == nullptr) return;
  Block* last = chain;
  while (last->next != nullptr) last = last->next;
  std::lock_guard lock(mutex_);
  last->next = free_;
  free_ = chain;
}

std::size_t BlockPool::bytes_reserved() const {
  std::lock_guard lock(mutex_);
  return bytes_reserved_;
}

BlockArena& BlockArena::operator=(BlockArena&& other) noexcept {
  if (this == &other) return *this;
  Reset();
  own_pool_ = std::move(other.own_pool_);
  pool_ = other.pool_;
  current_ = other.current_;
  used_ = other.used_;
  bytes_in_use_ = other.bytes_in_use_;
  other.current_ = nullptr;
  other.used_ = other.bytes_in_use_ = 0;
  return *this;
}

void BlockArena::SetPool(BlockPool& pool) {
  Reset();
  own_pool_.reset();
  pool_ = &pool;
}

}  // namespace strata
