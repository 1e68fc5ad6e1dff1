// A body's share of a stage, written as straight-line code that stops at each halo fill
// (`co_await halo_fill(...)`), so that a stage can run every body in rounds (run_in_rounds):
// each body runs until it needs halos; then, body after body, the fields each one waits for
// are filled in one exchange; then each goes on. Each body computes exactly what it computed
// alone, in the same order (only its fills come later), so no value changes. On 2 ranks
// capillary_coarse's step is 8 % shorter so (record
// verification/records/performance/body_rounds_s51): a rank no longer waits at a body's first
// fill while the other still computes a body it holds more of. One exchange for all the
// bodies of a round was tried and was slower (the same record).
//
// A body's work must touch only its own fields between fills; work that shares a buffer with
// the other bodies runs alone (run_now).
#pragma once

#include <coroutine>
#include <exception>
#include <initializer_list>
#include <span>
#include <vector>

namespace efsi {

class Field;
class HaloFiller;
struct Patch;
class StageTimers;

/// Where a chain of BodyWork frames stands: the halo fills its innermost frame waits for,
/// and that frame (null once the chain has ended).
struct WorkCursor {
    std::vector<Field*> fields;
    const Patch* patch = nullptr;
    int edge_layers = -1; ///< layers mirrored at the patch's own edges (HaloFiller::fill)
    std::coroutine_handle<> waiting;
};

/// A lazily started coroutine (it runs when awaited or run); `co_await` of a BodyWork runs
/// it inside the caller's chain, its halo fills becoming the caller's.
class [[nodiscard]] BodyWork {
  public:
    struct promise_type;
    using Handle = std::coroutine_handle<promise_type>;

    struct promise_type {
        WorkCursor* cursor = nullptr;
        std::coroutine_handle<> continuation; ///< the awaiting frame (null: a chain's root)
        std::exception_ptr error;

        BodyWork get_return_object() { return BodyWork(Handle::from_promise(*this)); }
        std::suspend_always initial_suspend() noexcept { return {}; }
        struct Final {
            bool await_ready() noexcept { return false; }
            std::coroutine_handle<> await_suspend(Handle h) noexcept {
                const std::coroutine_handle<> next = h.promise().continuation;
                return next ? next : std::noop_coroutine();
            }
            void await_resume() noexcept {}
        };
        Final final_suspend() noexcept { return {}; }
        void return_void() {}
        void unhandled_exception() { error = std::current_exception(); }
    };

    BodyWork() = default;
    explicit BodyWork(Handle h) : h_(h) {}
    BodyWork(BodyWork&& o) noexcept : h_(o.h_) { o.h_ = {}; }
    BodyWork& operator=(BodyWork&& o) noexcept {
        if (this != &o) {
            if (h_) h_.destroy();
            h_ = o.h_;
            o.h_ = {};
        }
        return *this;
    }
    BodyWork(const BodyWork&) = delete;
    BodyWork& operator=(const BodyWork&) = delete;
    ~BodyWork() {
        if (h_) h_.destroy();
    }

    /// Run inside the awaiting frame's chain; rethrows what the work threw.
    auto operator co_await() && noexcept {
        struct Awaiter {
            Handle child;
            bool await_ready() noexcept { return !child; }
            std::coroutine_handle<> await_suspend(Handle parent) noexcept {
                child.promise().cursor = parent.promise().cursor;
                child.promise().continuation = parent;
                return child;
            }
            void await_resume() {
                if (child && child.promise().error) std::rethrow_exception(child.promise().error);
            }
        };
        return Awaiter{h_};
    }

    /// Start the chain with `cursor` (run until its first fill or its end).
    void start(WorkCursor& cursor);
    /// Rethrow what the chain threw, once it has ended.
    void rethrow() const;

  private:
    Handle h_;
};

/// The awaitable of a halo fill: `co_await halo_fill({&a, &b}, patch)`.
struct HaloFill {
    std::vector<Field*> fields;
    const Patch* patch;
    int edge_layers;
    bool await_ready() const noexcept;
    void await_suspend(BodyWork::Handle h) noexcept {
        WorkCursor& c = *h.promise().cursor;
        c.fields = std::move(fields);
        c.patch = patch;
        c.edge_layers = edge_layers;
        c.waiting = h;
    }
    void await_resume() const noexcept {}
};

/// `edge_layers`: at the patch's own edges (no neighbour to exchange with) only that many
/// halo layers are mirrored (HaloFiller::fill); negative (the default): all of them.
inline HaloFill halo_fill(std::vector<Field*> fields, const Patch& patch, int edge_layers = -1) {
    return HaloFill{std::move(fields), &patch, edge_layers};
}
inline HaloFill halo_fill(Field& f, const Patch& patch) {
    return HaloFill{{&f}, &patch, -1};
}
/// All of `fields` (a tensor's components, say) in one fill.
HaloFill halo_fill(std::span<Field> fields, const Patch& patch);

/// Run the works (one per body, in the same body order on every rank) in rounds: each runs
/// until it waits for halos or ends, then each waiting work's fills are made (one
/// HaloFiller::fill per work, in body order), and the waiting works go on. Rethrows the
/// first error.
void run_in_rounds(std::span<BodyWork> works, const HaloFiller& halos);
/// One work alone, each fill made as it comes (what a plain function would do).
void run_now(BodyWork work, const HaloFiller& halos);

} // namespace efsi
