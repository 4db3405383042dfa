// The sealed CollisionModel: construction (arrays + query data) and the
// validating factory.
#include <memory>

#include "cmkit/model.h"
#include "cmkit/validate.h"
#include "model/model_access.h"
#include "model/query_data.h"
#include "util/assert.h"

namespace cmkit {

CollisionModel::CollisionModel(ModelArrays arrays)
    : data_(std::move(arrays)), queryData_(detail::makeQueryData(data_)) {}

Result<ModelPtr> CollisionModel::create(ModelArrays arrays) {
  // The first few are enough to say what is wrong.
  constexpr std::size_t kReported = 5;
  const std::vector<Violation> broken = structureViolations(arrays, kReported);
  if (!broken.empty()) {
    std::string message = "the model's arrays are not a valid collision model:";
    for (const Violation& v : broken) message += "\n  " + v.toString();
    return Error(message);
  }
  return std::shared_ptr<const CollisionModel>(new CollisionModel(std::move(arrays)));
}

namespace detail {

ModelPtr ModelAccess::seal(ModelArrays arrays) {
  CMKIT_ASSERT(structureViolations(arrays, 1).empty());
  return std::shared_ptr<const CollisionModel>(new CollisionModel(std::move(arrays)));
}

}  // namespace detail

}  // namespace cmkit
