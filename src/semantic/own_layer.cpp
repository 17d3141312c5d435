#include "semantic/own_layer.h"

#include <map>
#include <utility>

namespace esdslam {
namespace {

// The registration mutex of `type`, made on first use. The map's own mutex is held only while
// looking the type up, never while a type's mutex is taken, so it adds no edge to the lock order.
std::mutex& TypeMutex(const std::string& type) {
  static std::mutex map_mutex;
  static std::map<std::string, std::mutex> mutexes;  // std::map nodes stay where they are
  const std::lock_guard<std::mutex> lock(map_mutex);
  return mutexes[type];
}

}  // namespace

ScopedLayerConstructor::ScopedLayerConstructor(std::string type, cv::dnn::LayerFactory::Constructor constructor)
    : type_(std::move(type)), lock_(TypeMutex(type_)) {
  cv::dnn::LayerFactory::registerLayer(type_, constructor);
}

ScopedLayerConstructor::~ScopedLayerConstructor() { cv::dnn::LayerFactory::unregisterLayer(type_); }

void OwnLayer::forward(cv::InputArrayOfArrays inputs_arr, cv::OutputArrayOfArrays outputs_arr,
                       cv::OutputArrayOfArrays internals_arr) {
  const int depth = inputs_arr.depth();
  if (preferableTarget == cv::dnn::DNN_TARGET_OPENCL_FP16 && (depth == CV_16S || depth == CV_16F)) {
    forward_fallback(inputs_arr, outputs_arr, internals_arr);
    return;
  }
  std::vector<cv::Mat> inputs, outputs;
  inputs_arr.getMatVector(inputs);
  outputs_arr.getMatVector(outputs);
  ForwardMats(inputs, outputs);
}

}  // namespace esdslam
