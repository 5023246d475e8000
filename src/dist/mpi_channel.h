// The Channel of a distributed render between the processes mpirun started, over Open MPI
// (MPI_COMM_WORLD, one tag per MessageKind, non-blocking sends, polled receives). Built
// only with MPI (LANCER_WITH_MPI); only the thread that made it may use it.
#pragma once

#include <memory>

#include "dist/channel.h"

namespace lancer {

class MpiChannel final : public Channel {
 public:
  // MPI_Init_thread (MPI_THREAD_FUNNELED: the render threads never call MPI). Throws
  // std::runtime_error when MPI cannot start.
  MpiChannel();
  // Waits for the sends in flight, then MPI_Finalize.
  ~MpiChannel() override;
  MpiChannel(const MpiChannel&) = delete;
  MpiChannel& operator=(const MpiChannel&) = delete;

  int rank() const override;
  int size() const override;
  void send(int to, MessageKind kind, std::vector<std::byte> bytes) override;
  std::optional<Message> receive() override;
  void flush() override;
  // MPI_Abort.
  [[noreturn]] void abort(int code) override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lancer
