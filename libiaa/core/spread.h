// How the items of a parallel loop (the render's root blocks, the octree's subtrees) are spread
// over the processes of a run, and how every process gets every item's result back. The library
// asks an optional Spread (Exec::spread) for its items; without one, a loop runs every item in this
// process, as always. The MPI implementation is libiaa/dist (dist/mpi_spread.h); the library
// itself never talks to MPI. Results never depend on the spread: each item is computed by the same
// code whichever process runs it, and the results are put together in item order.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

namespace iaa {

class ProgressPhase;

/// The work one process did in one loop.
struct RankLoad {
  std::uint64_t items = 0;  ///< items it computed
  std::uint64_t work = 0;   ///< their cost as the loop counts it (interval evaluations)
  double busy = 0;          ///< seconds from the start of the loop to its last item's end
  double idle = 0;          ///< seconds it then waited for the slowest process
};

/// The load balance of one spread loop: one RankLoad per process, the lead (rank 0) first.
struct SpreadBalance {
  std::vector<RankLoad> ranks;

  /// Largest work over the mean (1 = perfect balance); 1 for no or one process or no work.
  double max_over_mean() const {
    if (ranks.size() < 2) return 1.0;
    std::uint64_t sum = 0, most = 0;
    for (const RankLoad& r : ranks) {
      sum += r.work;
      most = std::max(most, r.work);
    }
    return sum == 0 ? 1.0 : double(most) * double(ranks.size()) / double(sum);
  }
};

/// Spreads the items of a loop over the processes of a run. Every process calls begin(), then
/// next() from any of its threads until it returns -1, then finish(), with the same item count.
class Spread {
 public:
  virtual ~Spread() = default;
  /// Number of processes sharing the loops, and this one's index (0 = the lead, which writes the
  /// outputs and draws the progress).
  virtual int size() const = 0;
  virtual int rank() const = 0;
  /// Starts a loop of `items` items. On the lead, `phase` (when not null) is advanced once for
  /// each item that another process finishes (the caller advances it for its own).
  virtual void begin(std::uint64_t items, const ProgressPhase* phase) = 0;
  /// The next item this process computes, or -1 when none is left. Thread-safe. May throw when
  /// the loop cannot go on (another process failed: the error is not this process's).
  virtual std::int64_t next() = 0;
  /// A thread of this process met an error in the loop, which will leave it: next() returns -1
  /// from now on, so that the other threads stop at once instead of computing the rest of the
  /// items. finish() is not called after it.
  virtual void fail() {}
  /// Ends the loop. On entry results[i] and work[i] are set for the items this process computed;
  /// on return every process holds every item's. Returns the loop's balance.
  virtual SpreadBalance finish(std::vector<std::string>& results,
                               std::vector<std::uint64_t>& work) = 0;
};

/// Appends the bytes of a trivially copyable value to an item's result.
template <class T>
void put_bytes(std::string& out, const T& v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

/// Reads back a value put_bytes() wrote at `pos`, and moves `pos` past it.
template <class T>
T take_bytes(const std::string& in, std::size_t& pos) {
  T v;
  std::memcpy(&v, in.data() + pos, sizeof v);
  pos += sizeof v;
  return v;
}

/// Appends the values of an array of trivially copyable values to an item's result, without
/// their count (put_vector() writes it first; append_rest() reads such an array to the end).
template <class T, class A>
void put_values(std::string& out, const std::vector<T, A>& v) {
  static_assert(std::is_trivially_copyable_v<T>);
  // An empty vector's data() may be null, which memcpy and append must never be given (UBSan).
  if (!v.empty()) out.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

/// Reads `n` values put_values() wrote at `pos` onto the end of `v`, and moves `pos` past them.
template <class T, class A>
void take_values(const std::string& in, std::size_t& pos, std::size_t n, std::vector<T, A>& v) {
  static_assert(std::is_trivially_copyable_v<T>);
  const std::size_t at = v.size();
  v.resize(at + n);
  if (n > 0) std::memcpy(static_cast<void*>(v.data() + at), in.data() + pos, n * sizeof(T));
  pos += n * sizeof(T);
}

/// Appends a vector of trivially copyable values to an item's result: its size, then its values.
template <class T, class A>
void put_vector(std::string& out, const std::vector<T, A>& v) {
  put_bytes(out, std::uint64_t(v.size()));
  put_values(out, v);
}

/// Reads back what put_vector() wrote at `pos` into `v` (replacing what it held).
template <class T, class A>
void take_vector(const std::string& in, std::size_t& pos, std::vector<T, A>& v) {
  v.clear();
  take_values(in, pos, std::size_t(take_bytes<std::uint64_t>(in, pos)), v);
}

/// Appends to `v` the values that fill the rest of `in` from `pos` (put_values() as the result's
/// last part). False when the rest is not a whole number of values.
template <class T, class A>
bool append_rest(const std::string& in, std::size_t pos, std::vector<T, A>& v) {
  const std::size_t bytes = in.size() - pos;
  if (bytes % sizeof(T) != 0) return false;
  take_values(in, pos, bytes / sizeof(T), v);
  return true;
}

}  // namespace iaa
