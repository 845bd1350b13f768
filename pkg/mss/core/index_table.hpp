// An open-addressing table of indices into a caller's list of distinct keys: the STL reader's vertex merging
// and the candidates' positions seen (a std::unordered_map / set takes a node per key: with this table the
// femur's read is about 15% faster).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace mss::detail {

/// Indices 0, 1, 2, ... of keys that the caller keeps in a list of its own, in the order they were added,
/// found by their hash: linear probing, at most half full, grown by doubling. The keys' order is the
/// caller's alone: the table's size changes where a key lies in it, never the index it gets.
class IndexTable {
public:
    /// Sized for about @p expected keys at once (at least 1024 slots): growing rehashes every key.
    explicit IndexTable(std::size_t expected = 0) {
        std::size_t size = 1024;
        while (size < 2 * expected) size *= 2;
        slots_.assign(size, -1);
    }

    /// The index of the key equal to the one sought (@p equal(i): whether key i is it; @p hash: its hash), or
    /// -1 after recording @p count, the number of keys so far, as its index: the caller then appends it.
    /// @p hashAt(i): the hash of key i (to rehash when the table grows).
    template <class Equal, class HashAt>
    int findOrAdd(std::uint64_t hash, std::size_t count, Equal&& equal, HashAt&& hashAt) {
        if (2 * (count + 1) > slots_.size()) grow(count, hashAt);
        const std::size_t mask = slots_.size() - 1;
        for (std::size_t s = std::size_t(hash) & mask;; s = (s + 1) & mask) {
            const int v = slots_[s];
            if (v < 0) {
                slots_[s] = static_cast<int>(count);
                return -1;
            }
            if (equal(v)) return v;
        }
    }

    /// Records, in an empty table, the @p count keys 0 .. count - 1, already distinct, with their hashes
    /// @p hashAt(i).
    template <class HashAt> void addAll(std::size_t count, HashAt&& hashAt) {
        if (2 * count > slots_.size()) return grow(count, hashAt); // which records them
        const std::size_t mask = slots_.size() - 1;
        for (std::size_t v = 0; v < count; ++v) {
            std::size_t s = std::size_t(hashAt(static_cast<int>(v))) & mask;
            while (slots_[s] >= 0) s = (s + 1) & mask;
            slots_[s] = static_cast<int>(v);
        }
    }

    /// Slots in use (the keys recorded): for tests.
    std::size_t used() const {
        std::size_t n = 0;
        for (int v : slots_) n += v >= 0;
        return n;
    }

private:
    template <class HashAt> void grow(std::size_t count, HashAt& hashAt) {
        std::size_t size = slots_.size() * 2;
        while (size < 2 * (count + 1)) size *= 2;
        slots_.assign(size, -1);
        addAll(count, hashAt);
    }
    std::vector<int> slots_;
};

} // namespace mss::detail
