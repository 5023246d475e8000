// A Channel between threads of one process, for testing the distributed render without
// MPI: one queue per rank, sends and receives that never block. With a seed it also hands a
// rank its messages out of order, further than MPI would (which keeps each sender's order):
// Unit and Result messages overtake one another, never a message of another kind from the
// same sender ahead of them; so the tests reach arrival orders one machine rarely gives.
#pragma once

#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "dist/channel.h"

namespace lancer::test {

// The queues every rank's channel shares.
class InProcessHub {
 public:
  // seed 0: each rank receives its messages in the order they were sent.
  explicit InProcessHub(int ranks, unsigned seed = 0)
      : queues_(static_cast<std::size_t>(ranks)), shuffle_(seed != 0), rng_(seed) {}

  int size() const { return static_cast<int>(queues_.size()); }

  void post(int to, Message m) {
    if (to < 0 || to >= size()) {
      std::fprintf(stderr, "in-process channel: a message from rank %d to rank %d\n", m.from, to);
      std::abort();
    }
    const std::lock_guard<std::mutex> lock(mutex_);
    ++posted_[{m.from, m.kind}];
    queues_[static_cast<std::size_t>(to)].push_back(std::move(m));
  }

  // Messages of `kind` rank `from` has sent so far.
  int posted(int from, MessageKind kind) {
    const std::lock_guard<std::mutex> lock(mutex_);
    const auto it = posted_.find({from, kind});
    return it == posted_.end() ? 0 : it->second;
  }

  std::optional<Message> take(int rank) {
    const std::lock_guard<std::mutex> lock(mutex_);
    std::deque<Message>& q = queues_[static_cast<std::size_t>(rank)];
    if (q.empty()) return std::nullopt;
    std::size_t pick = 0;
    if (shuffle_) {
      // A message may go first when nothing from its sender is ahead of it, or when it and
      // everything from its sender ahead of it are units or results.
      std::vector<std::size_t> free;
      std::set<int> seen, blocked;
      for (std::size_t i = 0; i < q.size(); ++i) {
        const bool movable = q[i].kind == MessageKind::Unit || q[i].kind == MessageKind::Result;
        if (!seen.count(q[i].from) || (movable && !blocked.count(q[i].from))) free.push_back(i);
        seen.insert(q[i].from);
        if (!movable) blocked.insert(q[i].from);
      }
      pick = free[std::uniform_int_distribution<std::size_t>(0, free.size() - 1)(rng_)];
    }
    Message m = std::move(q[pick]);
    q.erase(q.begin() + static_cast<std::ptrdiff_t>(pick));
    return m;
  }

 private:
  std::mutex mutex_;
  std::vector<std::deque<Message>> queues_;
  std::map<std::pair<int, MessageKind>, int> posted_;
  bool shuffle_;
  std::mt19937 rng_;
};

class InProcessChannel final : public Channel {
 public:
  InProcessChannel(InProcessHub& hub, int rank) : hub_(hub), rank_(rank) {}

  int rank() const override { return rank_; }
  int size() const override { return hub_.size(); }
  void send(int to, MessageKind kind, std::vector<std::byte> bytes) override {
    hub_.post(to, Message{rank_, kind, std::move(bytes)});
  }
  std::optional<Message> receive() override { return hub_.take(rank_); }
  void flush() override {}  // delivered when sent
  // Nothing in these tests should ever end every rank at once.
  [[noreturn]] void abort(int code) override {
    std::fprintf(stderr, "in-process channel: rank %d aborted the render (code %d)\n", rank_, code);
    std::abort();
  }

 private:
  InProcessHub& hub_;
  int rank_;
};

}  // namespace lancer::test
