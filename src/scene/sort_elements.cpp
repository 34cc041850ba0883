// Paper 2.3.1: element sorting, so elements that can share a mesh are
// adjacent in the drawing order, without ever moving an element across one
// it overlaps (the graph's edges).
//
// Two methods: the paper's SortElements (quadratic; kept faithful for
// comparison and small scenes) and ours, a topological sort of the graph
// (Kahn) that stays on the current mesh while it has elements ready, which
// is O((n + edges) log n). The default picks whichever gives fewer draws.
#include <algorithm>
#include <functional>
#include <unordered_map>

#include "scene/internal.h"

namespace depthcull::detail {

namespace {

// Elements with key >= 0, in painter's order.
std::vector<std::uint32_t> participating(const std::vector<std::int32_t>& keys) {
    std::vector<std::uint32_t> list;
    for (std::size_t i = 0; i < keys.size(); ++i)
        if (keys[i] >= 0) list.push_back(std::uint32_t(i));
    return list;
}

// Paper SortElements. Errata: after moving E_j to position i+1 the scan
// for E_i is done (E_j becomes the next E_i, which continues the run), so
// the loop terminates. E_j moves only when no element between them in the
// current order is one it overlaps (graph edge from j).
std::vector<std::uint32_t> paper_sort(const ElementGraph& graph, const std::vector<std::int32_t>& keys) {
    std::vector<std::uint32_t> order = participating(keys);
    const std::size_t m = order.size();
    std::vector<std::int64_t> pos(keys.size(), -1);
    for (std::size_t p = 0; p < m; ++p) pos[order[p]] = std::int64_t(p);
    for (std::size_t i = 0; i + 1 < m; ++i) {
        for (std::size_t j = i + 1; j < m; ++j) {
            if (keys[order[j]] != keys[order[i]]) continue; // CanShareMesh
            bool can_move = true;
            for (const std::uint32_t* b = graph.behind_begin(order[j]); b != graph.behind_end(order[j]); ++b) {
                if (keys[*b] >= 0 && pos[*b] > std::int64_t(i) && pos[*b] < std::int64_t(j)) {
                    can_move = false;
                    break;
                }
            }
            if (!can_move) continue;
            std::rotate(order.begin() + std::ptrdiff_t(i + 1), order.begin() + std::ptrdiff_t(j), order.begin() + std::ptrdiff_t(j + 1));
            for (std::size_t p = i + 1; p <= j; ++p) pos[order[p]] = std::int64_t(p);
            break;
        }
    }
    return order;
}

// Ours: Kahn's topological sort over "behind before front", choosing among
// ready elements one with the current mesh key while there is one (lowest
// index first, to stay close to painter's order), else the lowest-index
// ready element, whose key becomes current. (Switching to the key with the
// most ready elements instead was tried: 3x the draws on bench_scene's
// scenes, since it drains keys whose later elements are still blocked.)
std::vector<std::uint32_t> batch_sort(const ElementGraph& graph, const std::vector<std::int32_t>& keys) {
    const std::size_t n = keys.size();
    // Dense key ids, in order of first appearance (deterministic).
    std::unordered_map<std::int32_t, std::uint32_t> dense;
    std::vector<std::uint32_t> key_id(n, 0);
    for (std::size_t i = 0; i < n; ++i)
        if (keys[i] >= 0) key_id[i] = dense.emplace(keys[i], std::uint32_t(dense.size())).first->second;

    // Reverse edges (front lists) and in-degrees, among participants only.
    std::vector<std::uint32_t> indegree(n, 0), front_start(n + 1, 0);
    for (std::size_t i = 0; i < n; ++i) {
        if (keys[i] < 0) continue;
        for (const std::uint32_t* b = graph.behind_begin(i); b != graph.behind_end(i); ++b) {
            if (keys[*b] < 0) continue;
            ++indegree[i];
            ++front_start[*b + 1];
        }
    }
    for (std::size_t i = 1; i <= n; ++i) front_start[i] += front_start[i - 1];
    std::vector<std::uint32_t> front(front_start[n]);
    {
        std::vector<std::uint32_t> fill(front_start.begin(), front_start.end() - 1);
        for (std::size_t i = 0; i < n; ++i) {
            if (keys[i] < 0) continue;
            for (const std::uint32_t* b = graph.behind_begin(i); b != graph.behind_end(i); ++b)
                if (keys[*b] >= 0) front[fill[*b]++] = std::uint32_t(i);
        }
    }

    using MinHeap = std::vector<std::uint32_t>;
    const auto greater = std::greater<std::uint32_t>();
    std::vector<MinHeap> ready(dense.size());
    MinHeap any_ready; // lazy: may hold emitted elements
    std::vector<std::uint8_t> emitted(n, 0);
    auto push = [&](std::uint32_t e) {
        ready[key_id[e]].push_back(e);
        std::push_heap(ready[key_id[e]].begin(), ready[key_id[e]].end(), greater);
        any_ready.push_back(e);
        std::push_heap(any_ready.begin(), any_ready.end(), greater);
    };
    std::size_t m = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (keys[i] < 0) continue;
        ++m;
        if (indegree[i] == 0) push(std::uint32_t(i));
    }
    std::vector<std::uint32_t> order;
    order.reserve(m);
    std::int64_t current = -1;
    while (order.size() < m) {
        if (current < 0 || ready[std::size_t(current)].empty()) {
            while (emitted[any_ready.front()]) {
                std::pop_heap(any_ready.begin(), any_ready.end(), greater);
                any_ready.pop_back();
            }
            current = key_id[any_ready.front()];
        }
        MinHeap& h = ready[std::size_t(current)];
        std::pop_heap(h.begin(), h.end(), greater);
        std::uint32_t e = h.back();
        h.pop_back();
        emitted[e] = 1;
        order.push_back(e);
        for (std::uint32_t k = front_start[e]; k < front_start[e + 1]; ++k)
            if (--indegree[front[k]] == 0) push(front[k]);
    }
    return order;
}

} // namespace

std::int64_t count_runs(const std::vector<std::uint32_t>& order, const std::vector<std::int32_t>& keys) {
    std::int64_t runs = 0;
    std::int32_t last = -1;
    for (std::uint32_t e : order) {
        if (keys[e] < 0) continue;
        if (keys[e] != last) ++runs;
        last = keys[e];
    }
    return runs;
}

std::vector<std::uint32_t> sort_order(const ElementGraph& graph, const std::vector<std::int32_t>& keys, SortMethod method) {
    switch (method) {
    case SortMethod::none: return participating(keys);
    case SortMethod::paper: return paper_sort(graph, keys);
    case SortMethod::batch: break;
    }
    std::vector<std::uint32_t> best = batch_sort(graph, keys);
    std::int64_t best_runs = count_runs(best, keys);
    auto consider = [&](std::vector<std::uint32_t> order) {
        std::int64_t runs = count_runs(order, keys);
        if (runs < best_runs) {
            best = std::move(order);
            best_runs = runs;
        }
    };
    std::vector<std::uint32_t> plain = participating(keys);
    if (plain.size() <= kPaperSortMaxElements) consider(paper_sort(graph, keys));
    consider(std::move(plain));
    return best;
}

} // namespace depthcull::detail

namespace depthcull {

std::vector<std::uint32_t> sort_elements(const Scene& scene, const ElementGraph& graph, SortMethod method) {
    return detail::sort_order(graph, detail::mesh_keys(scene), method);
}

std::int64_t count_batches(const Scene& scene, const std::vector<std::uint32_t>& order) {
    return detail::count_runs(order, detail::mesh_keys(scene));
}

} // namespace depthcull
