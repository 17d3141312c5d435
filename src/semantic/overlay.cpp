#include "semantic/overlay.h"

#include <opencv2/imgproc.hpp>

#include "common/error.h"

namespace esdslam {

cv::Vec3b VocColorBgr(int class_id) {
  // VOC palette: bits of the id spread over the colour channels, most significant first.
  int r = 0, g = 0, b = 0;
  for (int shift = 7, id = class_id; id > 0; --shift, id >>= 3) {
    r |= ((id >> 0) & 1) << shift;
    g |= ((id >> 1) & 1) << shift;
    b |= ((id >> 2) & 1) << shift;
  }
  return cv::Vec3b(static_cast<uchar>(b), static_cast<uchar>(g), static_cast<uchar>(r));
}

cv::Mat DrawLabelOverlay(const cv::Mat& bgr, const cv::Mat& labels, double alpha) {
  if (bgr.type() != CV_8UC3 || labels.type() != CV_8UC1 || bgr.size() != labels.size())
    throw Error("DrawLabelOverlay: need a CV_8UC3 image and CV_8UC1 labels of the same size");
  cv::Mat lut(1, 256, CV_8UC3);
  for (int i = 0; i < 256; ++i) lut.at<cv::Vec3b>(i) = VocColorBgr(i);
  cv::Mat labels3, colours, blended;
  cv::cvtColor(labels, labels3, cv::COLOR_GRAY2BGR);
  cv::LUT(labels3, lut, colours);
  cv::addWeighted(bgr, 1.0 - alpha, colours, alpha, 0.0, blended);
  cv::Mat out = bgr.clone();
  blended.copyTo(out, labels != 0);
  // Class borders: pixels whose 3x3 neighbourhood holds another label.
  cv::Mat dilated, eroded;
  cv::dilate(labels, dilated, cv::Mat());
  cv::erode(labels, eroded, cv::Mat());
  colours.copyTo(out, dilated != eroded);
  return out;
}

}  // namespace esdslam
