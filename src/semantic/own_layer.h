#pragma once
// What this project's OpenCV DNN layers (semantic/resize_layer.h, grouped_conv_layer.h,
// concat_layer.h) share: the scoped registration of a layer constructor, and the base class with
// the forward pass on float blobs.

#include <mutex>
#include <string>
#include <vector>

#include <opencv2/dnn.hpp>

namespace esdslam {

// While an instance lives, the layers of `type` that OpenCV DNN creates (cv::dnn::readNetFromONNX
// creates every layer while importing; Net::addLayer) come from `constructor`. OpenCV's
// LayerFactory keeps a stack of constructors per type: the constructor pushes `constructor` on
// top of OpenCV's own, the destructor pops it, so OpenCV's constructor is the one in force again
// afterwards. The registration is process-wide: one instance per type at a time (a mutex per
// type, held for the instance's life; instances of different types are independent), and a net
// loaded on another thread meanwhile also gets this constructor's layers. Nets already loaded
// keep the layers they were built with. Where one thread holds several types, it takes them in
// the order docs/CORE.md ("Segmenter model loading") gives.
class ScopedLayerConstructor {
 public:
  ScopedLayerConstructor(std::string type, cv::dnn::LayerFactory::Constructor constructor);
  ~ScopedLayerConstructor();
  ScopedLayerConstructor(const ScopedLayerConstructor&) = delete;
  ScopedLayerConstructor& operator=(const ScopedLayerConstructor&) = delete;

 private:
  std::string type_;
  std::unique_lock<std::mutex> lock_;  // the type's mutex
};

// Base of this project's layers: OpenCV's CPU backend only, float blobs. forward hands half-float
// blobs (the OpenCL FP16 target) to OpenCV's forward_fallback, which converts them to float and
// calls forward again, as for OpenCV's own layers (a path the tests do not take: the segmenter
// runs on the CPU target, in float); it passes the rest to ForwardMats.
class OwnLayer : public cv::dnn::Layer {
 public:
  using cv::dnn::Layer::forward;

  bool supportBackend(int backend_id) override { return backend_id == cv::dnn::DNN_BACKEND_OPENCV; }

  void forward(cv::InputArrayOfArrays inputs_arr, cv::OutputArrayOfArrays outputs_arr,
               cv::OutputArrayOfArrays internals_arr) final;

 protected:
  // The layer's computation: `outputs` are allocated to the shapes getMemoryShapes gave.
  virtual void ForwardMats(const std::vector<cv::Mat>& inputs, std::vector<cv::Mat>& outputs) = 0;
};

}  // namespace esdslam
