// Byte buffers for MPI messages, in waLBerla's SendBuffer/RecvBuffer manner: values are written
// field by field with memcpy, so the wire format is explicit and independent of struct padding.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "polydem/core/error.h"
#include "polydem/core/types.h"

namespace polydem {

class SendBuffer {
 public:
  template <typename T>
  requires std::is_arithmetic_v<T> SendBuffer& operator<<(const T& value) {
    append(&value, sizeof value);
    return *this;
  }
  SendBuffer& operator<<(const Vec3& v) { return *this << v.x() << v.y() << v.z(); }
  SendBuffer& operator<<(const Quat& q) { return *this << q.w() << q.x() << q.y() << q.z(); }

  void append(const void* data, std::size_t bytes) {
    const auto* p = static_cast<const std::byte*>(data);
    bytes_.insert(bytes_.end(), p, p + bytes);
  }
  const std::vector<std::byte>& bytes() const { return bytes_; }
  std::vector<std::byte>& bytes() { return bytes_; }
  std::size_t size() const { return bytes_.size(); }
  void clear() { bytes_.clear(); }

 private:
  std::vector<std::byte> bytes_;
};

class RecvBuffer {
 public:
  RecvBuffer() = default;
  RecvBuffer(const std::byte* data, std::size_t size) : data_(data), size_(size) {}

  template <typename T>
  requires std::is_arithmetic_v<T> RecvBuffer& operator>>(T& value) {
    take(&value, sizeof value);
    return *this;
  }
  RecvBuffer& operator>>(Vec3& v) { return *this >> v.x() >> v.y() >> v.z(); }
  RecvBuffer& operator>>(Quat& q) { return *this >> q.w() >> q.x() >> q.y() >> q.z(); }

  void take(void* out, std::size_t bytes) {
    if (pos_ + bytes > size_) throw Error("message buffer read past its end (corrupted message)");
    std::memcpy(out, data_ + pos_, bytes);
    pos_ += bytes;
  }
  bool atEnd() const { return pos_ == size_; }
  std::size_t remaining() const { return size_ - pos_; }

 private:
  const std::byte* data_ = nullptr;
  std::size_t size_ = 0;
  std::size_t pos_ = 0;
};

}  // namespace polydem
