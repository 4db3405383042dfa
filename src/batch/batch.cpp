// batch.cpp: the batch forms of the queries (cmkit/batch.h): a chunked
// parallel loop over independent single queries.
#include "cmkit/batch.h"

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

namespace cmkit {
namespace {

// Chunks are small enough to balance a few threads and to report progress
// often, large enough that taking one costs nothing against its queries.
constexpr std::size_t kChunksPerBatch = 256;
constexpr std::size_t kMinChunk = 16;
constexpr std::size_t kMaxChunk = 4096;
// Ray batches: fewer, larger chunks (see castRayBatch).
constexpr std::size_t kRayChunksPerBatch = 16;
constexpr std::size_t kMaxRayChunk = 12288;
// How often the calling thread looks at the helpers' progress when no
// notification came (one can be missed between its check and its wait).
constexpr int kProgressPollMs = 20;

std::size_t chunkSizeFor(std::size_t n, const BatchOptions& options) {
  if (options.chunkSize > 0) return options.chunkSize;
  return std::clamp((n + kChunksPerBatch - 1) / kChunksPerBatch, kMinChunk, kMaxChunk);
}

Status checkOut(std::size_t outSize, std::size_t n) {
  if (outSize == n) return Ok{};
  return Error("batch output holds " + std::to_string(outSize) + " results for " + std::to_string(n) +
               " queries");
}

// Runs body(begin, end, work) over [0, n) in chunks on the workers; see the
// contract in batch.h.
template <class Body>
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
      QueryWork queryWork;
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

template <class T>
const T& pick(std::span<const T> values, std::size_t i) {
  return values[values.size() == 1 ? 0 : i];
}

}  // namespace

Result<std::size_t> batchSize(std::size_t a, std::size_t b, const char* what) {
  if (a == b || b == 1) return a;
  if (a == 1) return b;
  return Error(std::string("batch inputs of different lengths: ") + what + " (" + std::to_string(a) +
               " and " + std::to_string(b) + "; each must be 1 or the batch size)");
}

namespace {

// The batch size of two "1 or N" inputs, checked against the output's length.
Result<std::size_t> pairedSize(std::size_t a, std::size_t b, const char* what, std::size_t outSize) {
  auto n = batchSize(a, b, what);
  if (!n) return n;
  if (auto s = checkOut(outSize, *n); !s) return s.error();
  return n;
}

}  // namespace

Status translateBatch(const CollisionModel& model, const TranslationBatch& batch, std::span<TraceResult> out,
                      const BatchOptions& options) {
  const auto n = pairedSize(batch.starts.size(), batch.ends.size(), "starts and ends", out.size());
  if (!n) return n.error();
  return runChunks(*n, options, [&](std::size_t begin, std::size_t end, QueryWork& work) {
    TranslationQuery q = batch.query;
    for (std::size_t i = begin; i < end; ++i) {
      q.start = pick(batch.starts, i);
      q.end = pick(batch.ends, i);
      out[i] = translate(model, q, work);
    }
  });
}

Status rotateBatch(const CollisionModel& model, const RotationBatch& batch, std::span<TraceResult> out,
                   const BatchOptions& options) {
  const auto n = pairedSize(batch.starts.size(), batch.rotations.size(), "starts and rotations", out.size());
  if (!n) return n.error();
  return runChunks(*n, options, [&](std::size_t begin, std::size_t end, QueryWork& work) {
    RotationQuery q = batch.query;
    for (std::size_t i = begin; i < end; ++i) {
      q.start = pick(batch.starts, i);
      q.rotation = pick(batch.rotations, i);
      out[i] = rotate(model, q, work);
    }
  });
}

Status contentsBatch(const CollisionModel& model, const ContentsBatch& batch, std::span<ContentsResult> out,
                     const BatchOptions& options) {
  if (auto s = checkOut(out.size(), batch.positions.size()); !s) return s;
  return runChunks(batch.positions.size(), options, [&](std::size_t begin, std::size_t end, QueryWork& work) {
    ContentsQuery q = batch.query;
    for (std::size_t i = begin; i < end; ++i) {
      q.position = batch.positions[i];
      out[i] = contentsTest(model, q, work);
    }
  });
}

Status contactsBatch(const CollisionModel& model, const ContactsBatch& batch, std::span<ContactsResult> out,
                     const BatchOptions& options) {
  // starts, dirs (unless rotations stand without them) and rotations (when
  // given): each 1 or N.
  const bool turning = !batch.rotations.empty();
  const bool sharedDir = turning && batch.dirs.empty();
  Result<std::size_t> n = batch.starts.size();
  if (!sharedDir) n = batchSize(*n, batch.dirs.size(), "starts and dirs");
  if (n && turning) n = batchSize(*n, batch.rotations.size(), "starts, dirs and rotations");
  if (!n) return n.error();
  if (auto s = checkOut(out.size(), *n); !s) return s;
  return runChunks(*n, options, [&](std::size_t begin, std::size_t end, QueryWork& work) {
    ContactsQuery q = batch.query;
    for (std::size_t i = begin; i < end; ++i) {
      q.start = pick(batch.starts, i);
      if (!sharedDir) q.dir = pick(batch.dirs, i);
      if (turning) q.rotation = pick(batch.rotations, i);
      out[i] = contacts(model, q, work);
    }
  });
}

Status pointContentsBatch(const CollisionModel& model, const PointContentsBatch& batch,
                          std::span<PointContentsResult> out, const BatchOptions& options) {
  if (auto s = checkOut(out.size(), batch.points.size()); !s) return s;
  return runChunks(batch.points.size(), options, [&](std::size_t begin, std::size_t end, QueryWork& work) {
    PointContentsQuery q = batch.query;
    for (std::size_t i = begin; i < end; ++i) {
      q.point = batch.points[i];
      out[i] = pointContents(model, q, work);
    }
  });
}

Status castRayBatch(const RayIndex& index, const RayBatch& batch, std::span<RayHit> out,
                    const BatchOptions& options) {
  const auto n = pairedSize(batch.starts.size(), batch.ends.size(), "starts and ends", out.size());
  if (!n) return n.error();
  // Larger chunks than the other batches': RayIndex::castMany sorts each
  // chunk's rays into packets, and more rays give more coherent packets.
  BatchOptions rayOptions = options;
  if (rayOptions.chunkSize == 0)
    rayOptions.chunkSize = std::clamp<std::size_t>(*n / kRayChunksPerBatch, kMinChunk, kMaxRayChunk);
  return runChunks(*n, rayOptions, [&](std::size_t begin, std::size_t end, QueryWork&) {
    const auto part = [&](std::span<const Vec3> v) {
      return v.size() == 1 ? v : v.subspan(begin, end - begin);
    };
    index.castMany({batch.query, part(batch.starts), part(batch.ends)}, out.subspan(begin, end - begin));
  });
}

}  // namespace cmkit
