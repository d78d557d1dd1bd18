#include "bpm/context.h"

#include "bpm/errors.h"

namespace bpm {

void Context::report(double fraction, const std::string& stage) const {
    if (progress && !progress(fraction, stage)) throw Cancelled();
}

}  // namespace bpm
