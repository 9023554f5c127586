#include "talus/parallel/node_halo.hpp"

#include <bit>
#include <cstring>

namespace talus {

template <int Dim>
void NodeHalo<Dim>::connect(const Decomposition<Dim>& decomposition,
                            const ActiveNodes<Dim>& nodes) {
  decomposition_ = &decomposition;
  const Decomposition<Dim>& dec = decomposition;
  const std::vector<int>& neighbours = dec.neighbours();
  // To each neighbour, the lattice ids of the active nodes its points may reach; from it, the
  // same of its nodes. Both lists ascend, so their intersection is one merge, and it is the
  // same on both sides: a node both hold lies within both reaches.
  std::vector<std::vector<double>> to(neighbours.size());
  for (std::size_t k = 0; k < neighbours.size(); ++k)
    for (Index n = 0; n < nodes.size(); ++n)
      if (dec.reaches(neighbours[k], nodes.position(n)))
        to[k].push_back(std::bit_cast<double>(nodes.lattice_id(n)));
  const auto from = dec.comm().exchange(neighbours, to);

  peers_.clear();
  with_peer_.clear();
  for (std::size_t k = 0; k < neighbours.size(); ++k) {
    std::vector<Index> common;
    for (const double id : from[k])
      if (const Index n = nodes.find_lattice_id(std::bit_cast<Index>(id)); n >= 0)
        common.push_back(n);
    if (common.empty())
      continue;
    peers_.push_back(neighbours[k]);
    with_peer_.push_back(std::move(common));
  }
  shared_.clear();
  for (const auto& list : with_peer_)
    shared_.insert(shared_.end(), list.begin(), list.end());
  std::sort(shared_.begin(), shared_.end());
  shared_.erase(std::unique(shared_.begin(), shared_.end()), shared_.end());
  const int me = dec.comm().rank();
  lowest_.assign(shared_.size(), me);
  slot_.assign(peers_.size(), {});
  for (std::size_t k = 0; k < peers_.size(); ++k)
    for (const Index n : with_peer_[k]) {
      const auto s = static_cast<std::size_t>(std::lower_bound(shared_.begin(), shared_.end(), n) -
                                              shared_.begin());
      slot_[k].push_back(s);
      lowest_[s] = std::min(lowest_[s], peers_[k]);
    }
}

template <int Dim> void NodeHalo<Dim>::sum(std::span<const Field> fields) {
  if (peers_.empty())
    return;
  int width = 0;
  for (const Field& f : fields)
    width += f.width;
  const auto w = static_cast<std::size_t>(width);
  auto pack = [&](Index n, double* out) {
    for (const Field& f : fields)
      for (int c = 0; c < f.width; ++c)
        *out++ = f.values[static_cast<std::size_t>(n) * static_cast<std::size_t>(f.width) +
                          static_cast<std::size_t>(c)];
  };
  std::vector<std::vector<double>> to(peers_.size());
  for (std::size_t k = 0; k < peers_.size(); ++k) {
    to[k].resize(with_peer_[k].size() * w);
    for (std::size_t i = 0; i < with_peer_[k].size(); ++i)
      pack(with_peer_[k][i], to[k].data() + i * w);
  }
  const auto from = decomposition_->comm().exchange(peers_, to);
  // Totals in rank order: the ranks below this one, this one, the ranks above.
  std::vector<double> total(shared_.size() * w, 0.0), own(w);
  const int me = decomposition_->comm().rank();
  bool own_added = false;
  auto add_own = [&] {
    for (std::size_t s = 0; s < shared_.size(); ++s) {
      pack(shared_[s], own.data());
      for (std::size_t c = 0; c < w; ++c)
        total[s * w + c] += own[c];
    }
    own_added = true;
  };
  for (std::size_t k = 0; k < peers_.size(); ++k) { // peers_ ascend (neighbours do)
    if (!own_added && peers_[k] > me)
      add_own();
    for (std::size_t i = 0; i < slot_[k].size(); ++i)
      for (std::size_t c = 0; c < w; ++c)
        total[slot_[k][i] * w + c] += from[k][i * w + c];
  }
  if (!own_added)
    add_own();
  for (std::size_t s = 0; s < shared_.size(); ++s) {
    const double* t = total.data() + s * w;
    for (const Field& f : fields)
      for (int c = 0; c < f.width; ++c)
        f.values[static_cast<std::size_t>(shared_[s]) * static_cast<std::size_t>(f.width) +
                 static_cast<std::size_t>(c)] = *t++;
  }
}

template <int Dim>
typename NodeHalo<Dim>::NeighbourNodes
NodeHalo<Dim>::neighbour_nodes(const ActiveNodes<Dim>& nodes, std::span<const double> values,
                               int width) const {
  const Decomposition<Dim>& dec = *decomposition_;
  const std::vector<int>& neighbours = dec.neighbours();
  const auto w = static_cast<std::size_t>(width);
  std::vector<std::vector<double>> to(neighbours.size());
  for (std::size_t k = 0; k < neighbours.size(); ++k)
    for (Index n = 0; n < nodes.size(); ++n)
      if (dec.reaches(neighbours[k], nodes.position(n))) {
        to[k].push_back(std::bit_cast<double>(nodes.lattice_id(n)));
        const auto first =
            values.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(n) * w);
        to[k].insert(to[k].end(), first, first + static_cast<std::ptrdiff_t>(w));
      }
  const auto from = dec.comm().exchange(neighbours, to);
  NeighbourNodes out;
  for (std::size_t k = 0; k < neighbours.size(); ++k)
    for (std::size_t i = 0; i + w < from[k].size() + 1; i += w + 1) {
      out.rank.push_back(neighbours[k]);
      out.lattice_id.push_back(std::bit_cast<Index>(from[k][i]));
      out.values.insert(out.values.end(), from[k].begin() + static_cast<std::ptrdiff_t>(i + 1),
                        from[k].begin() + static_cast<std::ptrdiff_t>(i + 1 + w));
    }
  return out;
}

template class NodeHalo<2>;
template class NodeHalo<3>;

} // namespace talus
