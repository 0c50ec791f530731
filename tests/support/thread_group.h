/// \file thread_group.h
/// A ProcessGroup of threads in one process, for tests of distributed rendering without
/// mpirun: member b renders band b of the rows on its own thread, and at each exchange the
/// members copy each other's bands out of the buffers every member posts, as the ranks' MPI
/// all-gather does (runtime/distributed/mpi_comm.cpp). Every member must reach each exchange
/// (a std::barrier), as every rank must.
#pragma once

#include <barrier>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <thread>
#include <vector>

#include "runtime/driver/process_group.h"

namespace crex::testing {

class ThreadGroup {
public:
    explicit ThreadGroup(int bands) : bands_(bands), barrier_(bands), rows_(static_cast<size_t>(bands)), sums_(static_cast<size_t>(bands)) {
        members_.reserve(static_cast<size_t>(bands));
        for (int b = 0; b < bands; ++b) members_.emplace_back(*this, b);
    }

    /// Runs `work(member)` for every member on a thread of its own; returns when all are done.
    void run(const std::function<void(ProcessGroup& member)>& work) {
        std::vector<std::thread> threads;
        for (auto& m : members_) threads.emplace_back([&work, &m] { work(m); });
        for (auto& t : threads) t.join();
    }

private:
    class Member final : public ProcessGroup {
    public:
        Member(ThreadGroup& group, int band) : group_(group), band_(band) {}
        int bands() const override { return group_.bands_; }
        int band() const override { return band_; }
        bool leads() const override { return band_ == 0; }
        bool saves_cache_file() const override { return band_ == 0; }
        void share_rows(SharedRows& rows) override { group_.share_rows(band_, rows); }
        void sum(std::vector<double>& values) override { group_.sum(band_, values); }

    private:
        ThreadGroup& group_;
        int band_;
    };

    // Each row-sized buffer of `rows`: its data and bytes per pixel, in the same order on every member.
    static std::vector<std::pair<char*, size_t>> buffers(SharedRows& rows) {
        std::vector<std::pair<char*, size_t>> out;
        const size_t pixels = rows.film.pixel_count();
        rows.film.for_each_buffer([&](void* data, size_t bytes) { out.emplace_back(static_cast<char*>(data), bytes); });
        if (rows.ambient.size() == 3 * pixels) out.emplace_back(reinterpret_cast<char*>(rows.ambient.data()), 3 * sizeof(double));
        for (std::vector<float>* left : rows.throughput_left)
            if (left->size() == 3 * pixels) out.emplace_back(reinterpret_cast<char*>(left->data()), 3 * sizeof(float));
        return out;
    }

    void share_rows(int band, SharedRows& rows) {
        rows_[static_cast<size_t>(band)] = &rows;
        barrier_.arrive_and_wait();  // every member's buffers are posted
        auto mine = buffers(rows);
        const size_t width = static_cast<size_t>(rows.film.width());
        for (int b = 0; b < bands_; ++b) {
            if (b == band) continue;
            SharedRows& theirs = *rows_[static_cast<size_t>(b)];
            auto from = buffers(theirs);
            if (from.size() != mine.size()) throw std::logic_error("members hold different buffers");
            const size_t begin = static_cast<size_t>(rows.bounds[static_cast<size_t>(b)]) * width;
            const size_t end = static_cast<size_t>(rows.bounds[static_cast<size_t>(b) + 1]) * width;
            for (size_t k = 0; k < mine.size(); ++k)
                std::memcpy(mine[k].first + begin * mine[k].second, from[k].first + begin * from[k].second, (end - begin) * mine[k].second);
        }
        barrier_.arrive_and_wait();  // nobody renders on before every member has copied
    }

    void sum(int band, std::vector<double>& values) {
        sums_[static_cast<size_t>(band)] = &values;
        barrier_.arrive_and_wait();
        std::vector<double> total(values.size(), 0.0);
        for (const std::vector<double>* v : sums_)  // in band order, as MPI's reduction on a fixed group
            for (size_t i = 0; i < total.size(); ++i) total[i] += (*v)[i];
        barrier_.arrive_and_wait();
        values = std::move(total);
    }

    int bands_;
    std::barrier<> barrier_;
    std::vector<SharedRows*> rows_;
    std::vector<std::vector<double>*> sums_;
    std::vector<Member> members_;
};

}  // namespace crex::testing
