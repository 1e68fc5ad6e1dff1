#include "parallel/redistribution.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <cstring>

namespace efsi {

void copy_box(const Box& part, const real* src, const Box& from, const Storage& sfrom, real* dst,
              const Box& to, const Storage& sto) {
    if (part.empty()) return;
    const std::size_t row = std::size_t(part.hi[0] - part.lo[0]);
    for (int k = part.lo[2]; k < part.hi[2]; ++k)
        for (int j = part.lo[1]; j < part.hi[1]; ++j)
            std::memcpy(dst + sto.index(to, part.lo[0], j, k),
                        src + sfrom.index(from, part.lo[0], j, k), row * sizeof(real));
}

void copy_box(const Box& part, const real* src, const Box& from, real* dst, const Box& to) {
    copy_box(part, src, from, Storage::dense(from), dst, to, Storage::dense(to));
}

Redistribution::Redistribution(MPI_Comm comm, std::vector<Box> from, std::vector<Box> to,
                               const Storage* sfrom, const Storage* sto)
    : comm_(comm), from_(std::move(from)), to_(std::move(to)) {
    int size = 1;
    MPI_Comm_rank(comm_, &rank_);
    MPI_Comm_size(comm_, &size);
    if (int(from_.size()) != size || int(to_.size()) != size)
        throw InputError("Redistribution: one box per rank is needed in each layout");
    sfrom_ = sfrom ? *sfrom : Storage::dense(from_[rank_]);
    sto_ = sto ? *sto : Storage::dense(to_[rank_]);
    send_count_.assign(size, 0);
    recv_count_.assign(size, 0);
    send_offset_.assign(size, 0);
    recv_offset_.assign(size, 0);
    int sent = 0, received = 0;
    for (int q = 0; q < size; ++q) {
        if (!(from_[q] == to_[q]) && !(from_[q].empty() && to_[q].empty())) identity_ = false;
        if (q == rank_) continue;
        send_offset_[q] = sent;
        recv_offset_[q] = received;
        send_count_[q] = int(
            intersect(from_[rank_], to_[q]).empty() ? 0 : intersect(from_[rank_], to_[q]).count());
        recv_count_[q] = int(
            intersect(from_[q], to_[rank_]).empty() ? 0 : intersect(from_[q], to_[rank_]).count());
        sent += send_count_[q];
        received += recv_count_[q];
    }
    send_.resize(std::size_t(sent));
    recv_.resize(std::size_t(received));
}

void Redistribution::run(const real* src, real* dst) {
    const Box& mine_from = from_[rank_];
    const Box& mine_to = to_[rank_];
    const int size = int(from_.size());
    for (int q = 0; q < size; ++q)
        if (q != rank_ && send_count_[q] > 0) {
            const Box part = intersect(mine_from, to_[q]);
            copy_box(part, src, mine_from, sfrom_, send_.data() + send_offset_[q], part,
                     Storage::dense(part));
        }
    // What this rank keeps is copied directly.
    copy_box(intersect(mine_from, mine_to), src, mine_from, sfrom_, dst, mine_to, sto_);
    if (size > 1)
        MPI_Alltoallv(send_.data(), send_count_.data(), send_offset_.data(), MPI_DOUBLE,
                      recv_.data(), recv_count_.data(), recv_offset_.data(), MPI_DOUBLE, comm_);
    for (int q = 0; q < size; ++q)
        if (q != rank_ && recv_count_[q] > 0) {
            const Box part = intersect(from_[q], mine_to);
            copy_box(part, recv_.data() + recv_offset_[q], part, Storage::dense(part), dst, mine_to,
                     sto_);
        }
}

} // namespace efsi
