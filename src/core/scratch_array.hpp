#pragma once
/// An array for scratch that is always written before it is read: resizing neither
/// keeps nor initialises its contents, and it reallocates only to grow, with a quarter of
/// headroom. (A std::vector<double> of a factor's panels, ~14 MB at 8k triangles, copied and
/// zero-filled what it gained at every re-analysis: 2.0–2.8 ms of pinch_move's 7 ms ones.)
#include <cstddef>
#include <memory>

namespace dexcloth {

template <class T>
class BasicScratchArray {
 public:
  /// size() becomes n; the contents are undefined.
  void resize(std::size_t n) {
    if (n > m_capacity) {
      m_capacity = n + n / 4;
      m_data.reset();  // free first: the old contents are not kept
      m_data.reset(new T[m_capacity]);
    }
    m_size = n;
  }
  std::size_t size() const { return m_size; }
  T* data() { return m_data.get(); }
  const T* data() const { return m_data.get(); }

 private:
  std::unique_ptr<T[]> m_data;
  std::size_t m_size{}, m_capacity{};
};

using ScratchArray = BasicScratchArray<double>;

}  // namespace dexcloth
