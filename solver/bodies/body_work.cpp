#include "bodies/body_work.hpp"

#include "bodies/patch.hpp"
#include "boundary/boundary.hpp"

namespace efsi {

bool HaloFill::await_ready() const noexcept {
    // Nothing to exchange (HaloFiller::fill skips empty patches): go straight on.
    return fields.empty() || patch->empty();
}

HaloFill halo_fill(std::span<Field> fields, const Patch& patch) {
    std::vector<Field*> of;
    for (Field& f : fields)
        of.push_back(&f);
    return HaloFill{std::move(of), &patch, -1};
}

void BodyWork::start(WorkCursor& cursor) {
    cursor.waiting = {};
    if (!h_) return;
    h_.promise().cursor = &cursor;
    h_.resume();
}

void BodyWork::rethrow() const {
    if (h_ && h_.done() && h_.promise().error) std::rethrow_exception(h_.promise().error);
}

namespace {

void resume(WorkCursor& cursor) {
    const std::coroutine_handle<> h = cursor.waiting;
    cursor.waiting = {};
    h.resume();
}

/// The halo fills the work waits for, in one exchange.
void fill(const WorkCursor& cursor, const HaloFiller& halos) {
    const std::vector<const Patch*> patches(cursor.fields.size(), cursor.patch);
    halos.fill(cursor.fields, patches, cursor.edge_layers);
}

} // namespace

void run_in_rounds(std::span<BodyWork> works, const HaloFiller& halos) {
    std::vector<WorkCursor> cursors(works.size());
    for (std::size_t q = 0; q < works.size(); ++q) {
        works[q].start(cursors[q]);
        works[q].rethrow();
    }
    for (;;) {
        bool waiting = false;
        for (const WorkCursor& c : cursors)
            if (c.waiting) {
                fill(c, halos);
                waiting = true;
            }
        if (!waiting) return;
        for (std::size_t q = 0; q < works.size(); ++q)
            if (cursors[q].waiting) {
                resume(cursors[q]);
                works[q].rethrow();
            }
    }
}

void run_now(BodyWork work, const HaloFiller& halos) {
    WorkCursor cursor;
    work.start(cursor);
    work.rethrow();
    while (cursor.waiting) {
        fill(cursor, halos);
        resume(cursor);
        work.rethrow();
    }
}

} // namespace efsi
