// pipeline::parallel_for: the one way the pipeline and the commands run
// work on threads (pipeline/parallel.h).
#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "depthcull/limits.h"
#include "pipeline/parallel.h"

namespace depthcull::pipeline {

void parallel_for(std::size_t n, unsigned threads, const std::function<void(std::size_t)>& fn) {
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    threads = unsigned(std::min<std::size_t>({std::size_t(threads), n, std::size_t(limits::kMaxThreads)}));
    if (threads <= 1) {
        for (std::size_t i = 0; i < n; ++i) fn(i);
        return;
    }
    std::atomic<std::size_t> next{0};
    std::atomic<bool> failed{false};
    std::exception_ptr error;
    std::size_t error_index = n;
    std::mutex error_mutex;
    auto work = [&] {
        for (std::size_t i; !failed && (i = next.fetch_add(1)) < n;) {
            try {
                fn(i);
            } catch (...) {
                // Keep the lowest index's error, as a serial run reports.
                std::lock_guard lock(error_mutex);
                if (i < error_index) {
                    error_index = i;
                    error = std::current_exception();
                }
                failed = true;
            }
        }
    };
    // The caller is one of the workers. A thread that cannot be started
    // (RLIMIT_NPROC, no memory for its stack) is not an error: the work is
    // taken by index from one counter, so those running, the caller at
    // least, take its share. Letting the std::system_error escape would
    // destroy joinable threads, which calls std::terminate.
    std::vector<std::thread> pool;
    try {
        pool.reserve(threads - 1);
        for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work);
    } catch (...) {
    }
    work();
    for (auto& t : pool) t.join();
    if (error) std::rethrow_exception(error);
}

} // namespace depthcull::pipeline
