// Binding outer parameters to the model's inner component (core/flatten/outers.h).

#include "core/flatten/outers.h"

#include <unordered_map>
#include <unordered_set>

#include "core/base/error.h"

namespace momenta::flatten_internal {

void ResolveOuters(FlattenContext* context) {
  FlatSystem& flat = context->flat;
  bool any = false;
  for (const FlatInstance& inst : flat.instances) any = any || !inst.type->outers.empty();
  if (!any) return;
  // The model's own components by name (the inner ones are top-level components).
  std::unordered_map<std::string, uint32_t> top;
  for (uint32_t k = 0; k < flat.instances.size(); ++k) {
    if (flat.instances[k].type->outers.empty()) continue;
    for (const auto& [prefix, type_name] : flat.instances[k].type->outers) top.emplace(prefix, UINT32_MAX);
  }
  for (uint32_t k = 0; k < flat.instances.size(); ++k) {
    auto it = top.find(flat.InstancePath(InstanceId(k)));
    if (it == top.end()) continue;
    it->second = k;
  }
  // The inner components' parameters by name, looked up once each instead of a scan of every
  // parameter per outer parameter (quadratic in the number of bodies).
  std::unordered_set<uint32_t> inner_instances;
  for (const auto& [prefix, k] : top) {
    if (k != UINT32_MAX) inner_instances.insert(k);
  }
  std::unordered_map<std::string, ParamId> inner_params;
  for (uint32_t q = 0; q < flat.parameters.size(); ++q) {
    const InstanceId i = flat.parameters[q].instance;
    if (i.valid() && inner_instances.count(i.value())) inner_params.emplace(flat.ParameterName(ParamId(q)), ParamId(q));
  }
  ExprPool& pool = *flat.pool;
  for (uint32_t q = 0; q < flat.parameters.size(); ++q) {
    const InstanceId i = flat.parameters[q].instance;
    if (!i.valid()) continue;
    const ComponentType* type = flat.instances[i.value()].type;
    if (type->outers.empty()) continue;
    const std::string name = flat.ParameterName(ParamId(q));
    const std::string path = flat.InstancePath(i);
    const std::string local = name.substr(path.size() + 1);
    for (const auto& [prefix, type_name] : type->outers) {
      if (local.compare(0, prefix.size() + 1, prefix + ".") != 0) continue;
      const uint32_t inner = top.at(prefix);
      if (inner == UINT32_MAX) break;  // no such component: the defaults stay
      const ComponentType* inner_type = flat.instances[inner].type;
      if (inner_type->name != type_name && inner_type->name.substr(inner_type->name.rfind('.') + 1) != type_name) {
        throw ModelError(flat.instances[inner].loc,
                         prefix + " is a " + inner_type->name + ", but " + path + " (" + type->name + ") needs the model's " +
                             prefix + " to be a " + type_name);
      }
      auto target = inner_params.find(prefix + "." + local.substr(prefix.size() + 1));
      if (target != inner_params.end()) flat.parameters[q].binding = pool.Param(target->second);
      break;
    }
  }
}

}  // namespace momenta::flatten_internal
