// run_chunks.h: the batches' chunked parallel loop (cmkit/batch.h's
// contract: chunks of a size that depends only on N, taken from a shared
// counter by the workers, the calling thread one of them; progress and
// cancelling on the calling thread). Shared by the single-model batches
// (batch.cpp) and the world's (world/world_batch.cpp), each worker owning a
// `Work` (QueryWork, WorldQueryWork).
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <new>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "cmkit/batch.h"

namespace cmkit::detail {

// Chunks are small enough to balance a few threads and to report progress
// often, large enough that taking one costs nothing against its queries.
inline constexpr std::size_t kChunksPerBatch = 256;
inline constexpr std::size_t kMinChunk = 16;
inline constexpr std::size_t kMaxChunk = 4096;
// Ray batches: fewer, larger chunks (see castRayBatch).
inline constexpr std::size_t kRayChunksPerBatch = 16;
inline constexpr std::size_t kMaxRayChunk = 12288;
// How often the calling thread looks at the helpers' progress when no
// notification came (one can be missed between its check and its wait).
inline constexpr int kProgressPollMs = 20;

inline std::size_t chunkSizeFor(std::size_t n, const BatchOptions& options) {
  if (options.chunkSize > 0) return options.chunkSize;
  return std::clamp((n + kChunksPerBatch - 1) / kChunksPerBatch, kMinChunk, kMaxChunk);
}

inline Status checkOut(std::size_t outSize, std::size_t n) {
  if (outSize == n) return Ok{};
  return Error("batch output holds " + std::to_string(outSize) + " results for " + std::to_string(n) +
               " queries");
}

// Runs body(begin, end, work) over [0, n) in chunks on the workers; see the
// contract in batch.h.
template <class Work, class Body>
Status runChunks(std::size_t n, const BatchOptions& options, const Body& body) {
  if (n == 0) return Ok{};
  const std::size_t chunk = chunkSizeFor(n, options);
  const std::size_t numChunks = (n + chunk - 1) / chunk;
  std::size_t threads = options.threads > 0 ? std::size_t(options.threads)
                                            : std::max<std::size_t>(1, std::thread::hardware_concurrency());
  threads = std::min(threads, numChunks);

  std::atomic<std::size_t> nextChunk{0};
  std::atomic<std::size_t> done{0};
  std::atomic<bool> stop{false};
  std::mutex errorMutex;
  std::optional<Error> error;
  const auto fail = [&](Error e) {
    const std::lock_guard lock(errorMutex);
    if (!error) error = std::move(e);
    stop = true;
  };
  const auto failFromException = [&](std::exception_ptr e, const char* where) {
    try {
      std::rethrow_exception(e);
    } catch (const std::bad_alloc&) {
      fail(Error(std::string("out of memory in ") + where));
    } catch (const std::exception& x) {
      fail(Error(std::string(where) + " failed: " + x.what()));
    } catch (...) {
      fail(Error(std::string(where) + " failed with an unknown exception"));
    }
  };

  // The caller reports progress (the hook runs on its thread only): after
  // each chunk it answers itself, then, once no chunk is left to take, each
  // time the helpers have answered more, until they are done.
  std::mutex progressMutex;
  std::condition_variable progressed;
  std::atomic<std::size_t> helpersRunning{0};
  const auto report = [&](std::size_t answered) {
    if (!options.progress) return;
    try {
      if (!options.progress(answered, n))
        fail(Error("batch cancelled after " + std::to_string(answered) + " of " + std::to_string(n) +
                   " queries"));
    } catch (...) {
      failFromException(std::current_exception(), "the batch progress hook");
    }
  };

  const auto work = [&](bool caller) {
    try {
      Work queryWork;
      while (!stop.load(std::memory_order_relaxed)) {
        const std::size_t c = nextChunk.fetch_add(1, std::memory_order_relaxed);
        if (c >= numChunks) break;
        const std::size_t begin = c * chunk;
        const std::size_t end = std::min(n, begin + chunk);
        body(begin, end, queryWork);
        const std::size_t answered = done.fetch_add(end - begin, std::memory_order_relaxed) + (end - begin);
        if (caller) {
          report(answered);
        } else if (options.progress) {
          progressed.notify_one();
        }
      }
    } catch (...) {
      failFromException(std::current_exception(), "a batch query");
    }
  };
  const auto helper = [&] {
    work(false);
    {
      const std::lock_guard lock(progressMutex);
      helpersRunning.fetch_sub(1);
    }
    progressed.notify_one();
  };

  std::vector<std::thread> helpers;
  try {
    helpers.reserve(threads - 1);
    for (std::size_t t = 1; t < threads; ++t) {
      helpersRunning.fetch_add(1);
      try {
        helpers.emplace_back(helper);
      } catch (...) {
        helpersRunning.fetch_sub(1);
        throw;
      }
    }
  } catch (...) {
    // Fewer threads than asked for: the ones running (and the caller) take every chunk.
  }
  work(true);
  if (options.progress) {
    std::size_t reported = done.load();
    std::unique_lock lock(progressMutex);
    while (helpersRunning.load() > 0 && !stop.load()) {
      // A notification sent between the check and the wait is caught by the timeout.
      progressed.wait_for(lock, std::chrono::milliseconds(kProgressPollMs));
      const std::size_t now = done.load();
      if (now != reported && now < n) {
        reported = now;
        lock.unlock();
        report(now);
        lock.lock();
      }
    }
  }
  for (auto& h : helpers) h.join();
  if (!error) report(n);  // everything answered; a false return still cancels (the caller asked to)
  if (error) return *error;
  return Ok{};
}

/// The batch size of two "1 or N" inputs, checked against the output's length.
inline Result<std::size_t> pairedSize(std::size_t a, std::size_t b, const char* what, std::size_t outSize) {
  auto n = batchSize(a, b, what);
  if (!n) return n;
  if (auto s = checkOut(outSize, *n); !s) return s.error();
  return n;
}

/// The value of a "1 or N" input for query i.
template <class T>
const T& pick(std::span<const T> values, std::size_t i) {
  return values[values.size() == 1 ? 0 : i];
}

}  // namespace cmkit::detail
