#include "run/halo_exchange.hpp"

namespace fibrodem {

HaloExchange::HaloExchange(RankGroup& ranks, const RankCells& share) : ranks_(ranks), neighbours_(share.neighbours) {
  send_.resize(neighbours_.size());
  receive_.resize(neighbours_.size());
  for (std::size_t k = 0; k < neighbours_.size(); ++k) {
    send_[k].resize(neighbours_[k].send.size());
    receive_[k].resize(neighbours_[k].receive.size());
    messages_.push_back({neighbours_[k].rank, send_[k].data(), send_[k].size(), receive_[k].data(), receive_[k].size()});
  }
}

void HaloExchange::refresh(double* V_mV) {
  for (std::size_t k = 0; k < neighbours_.size(); ++k) {
    const std::vector<int>& cells = neighbours_[k].send;
    for (std::size_t i = 0; i < cells.size(); ++i) send_[k][i] = V_mV[cells[i]];
  }
  ranks_.exchange(messages_);
  for (std::size_t k = 0; k < neighbours_.size(); ++k) {
    const std::vector<int>& cells = neighbours_[k].receive;
    for (std::size_t i = 0; i < cells.size(); ++i) V_mV[cells[i]] = receive_[k][i];
  }
  ++exchanges_;
}

}  // namespace fibrodem
