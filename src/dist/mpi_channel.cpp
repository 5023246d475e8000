#include "dist/mpi_channel.h"

#include <mpi.h>

#include <climits>
#include <stdexcept>
#include <string>
#include <utility>

namespace lancer {

struct MpiChannel::Impl {
  int rank = 0, size = 1;
  // Sends in flight and their buffers, which must live until each completes.
  std::vector<MPI_Request> requests;
  std::vector<std::vector<std::byte>> buffers;

  // Frees the buffers of the sends that have completed.
  void reap() {
    if (requests.empty()) return;
    std::vector<int> finished(requests.size());
    int count = 0;
    MPI_Testsome(static_cast<int>(requests.size()), requests.data(), &count, finished.data(), MPI_STATUSES_IGNORE);
    if (count <= 0) return;  // (MPI_UNDEFINED: none active)
    std::size_t kept = 0;
    for (std::size_t i = 0; i < requests.size(); ++i) {
      if (requests[i] == MPI_REQUEST_NULL) continue;
      if (kept != i) {  // (a vector moved onto itself would free the buffer MPI still sends from)
        requests[kept] = requests[i];
        buffers[kept] = std::move(buffers[i]);
      }
      ++kept;
    }
    requests.resize(kept);
    buffers.resize(kept);
  }
};

MpiChannel::MpiChannel() : impl_(std::make_unique<Impl>()) {
  int provided = 0;
  if (MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
    throw std::runtime_error("MPI could not start (MPI_Init_thread failed)");
  if (provided < MPI_THREAD_FUNNELED) {
    MPI_Finalize();
    throw std::runtime_error("this MPI cannot run threads beside MPI (MPI_THREAD_FUNNELED is missing)");
  }
  MPI_Comm_rank(MPI_COMM_WORLD, &impl_->rank);
  MPI_Comm_size(MPI_COMM_WORLD, &impl_->size);
}

MpiChannel::~MpiChannel() {
  flush();
  MPI_Finalize();
}

int MpiChannel::rank() const { return impl_->rank; }
int MpiChannel::size() const { return impl_->size; }

void MpiChannel::send(int to, MessageKind kind, std::vector<std::byte> bytes) {
  if (bytes.size() > static_cast<std::size_t>(INT_MAX))
    throw std::runtime_error("distributed render: a message of " + std::to_string(bytes.size()) + " bytes");
  impl_->reap();
  impl_->buffers.push_back(std::move(bytes));
  impl_->requests.push_back(MPI_REQUEST_NULL);
  std::vector<std::byte>& b = impl_->buffers.back();
  MPI_Isend(b.data(), static_cast<int>(b.size()), MPI_BYTE, to, static_cast<int>(kind), MPI_COMM_WORLD,
            &impl_->requests.back());
}

std::optional<Message> MpiChannel::receive() {
  impl_->reap();
  int flag = 0;
  MPI_Status status;
  MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status);
  if (!flag) return std::nullopt;
  int count = 0;
  MPI_Get_count(&status, MPI_BYTE, &count);
  Message m;
  m.from = status.MPI_SOURCE;
  m.kind = static_cast<MessageKind>(status.MPI_TAG);
  m.bytes.resize(static_cast<std::size_t>(count));
  MPI_Recv(m.bytes.data(), count, MPI_BYTE, status.MPI_SOURCE, status.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return m;
}

void MpiChannel::flush() {
  if (impl_->requests.empty()) return;
  MPI_Waitall(static_cast<int>(impl_->requests.size()), impl_->requests.data(), MPI_STATUSES_IGNORE);
  impl_->requests.clear();
  impl_->buffers.clear();
}

void MpiChannel::abort(int code) {
  MPI_Abort(MPI_COMM_WORLD, code);
  std::abort();  // (MPI_Abort does not return)
}

}  // namespace lancer
