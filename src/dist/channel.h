// How the ranks of a distributed render talk: tagged byte messages, sent without waiting
// for the receiver and received by polling, so that no rank ever blocks on another. MPI
// carries them between processes (mpi_channel.h); tests use an in-process one.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

namespace lancer {

enum class MessageKind : int {
  Ready = 1,   // worker -> 0, once: set up (or failed to), and with how many threads
  Unit = 2,    // 0 -> worker: a WorkUnit to render
  Result = 3,  // worker -> 0: a UnitResult
  Stop = 4,    // 0 -> worker: finish the unit in hand at its next wavefront, send it, then Done
  Done = 5,    // worker -> 0: nothing more will come from this rank
};

struct Message {
  int from = 0;
  MessageKind kind = MessageKind::Done;
  std::vector<std::byte> bytes;
};

class Channel {
 public:
  virtual ~Channel() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  // Queues the bytes for rank `to` and returns at once.
  virtual void send(int to, MessageKind kind, std::vector<std::byte> bytes) = 0;
  // A message that has arrived for this rank, if any; never blocks.
  virtual std::optional<Message> receive() = 0;
  // Returns once everything sent has been delivered.
  virtual void flush() = 0;
  // Ends every rank at once: for a failure in the middle of a render, when the others can
  // no longer be told to stop in order.
  [[noreturn]] virtual void abort(int code) = 0;
};

}  // namespace lancer
