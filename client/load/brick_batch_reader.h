#pragma once

#include <google/protobuf/io/zero_copy_stream.h>

#include <cstdint>
#include <string>
#include <vector>

#include "soltex/common/brick_key.h"

namespace soltex::load {

// What soltex-load needs of one `BrickBatch` (docs/PROTOCOL.md, section 6), read straight from
// the received bytes: keys, payload sizes, checksums and error codes. Payloads are skipped
// unless asked for, so a message costs no allocation or copy per brick; under load that is
// most of what parsing it as a protobuf message cost. Fields it does not know are skipped,
// as protobuf would.
class BrickBatchReader {
 public:
  struct Brick {
    BrickKey key;
    int32_t codec = 0;
    uint64_t checksum = 0;
    std::size_t payload_size = 0;
    std::size_t payload_offset = 0;  // in payloads(), when kept
  };
  struct Error {
    BrickKey key;
    int32_t code = 0;
  };

  // Reads one message; false when its bytes are not a valid BrickBatch (what was read of it
  // is then meaningless). With keep_payloads, payloads() holds the payloads back to back.
  bool read(google::protobuf::io::ZeroCopyInputStream& message, bool keep_payloads);

  const std::vector<Brick>& bricks() const { return bricks_; }
  const std::vector<Error>& errors() const { return errors_; }
  const std::vector<int32_t>& request_errors() const { return request_errors_; }
  const std::string& payloads() const { return payloads_; }

 private:
  std::vector<Brick> bricks_;
  std::vector<Error> errors_;
  std::vector<int32_t> request_errors_;
  std::string payloads_;
};

}  // namespace soltex::load
