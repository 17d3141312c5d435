#pragma once
// Forward declarations and id-ordered comparators. Containers keyed by map objects are ordered by
// the objects' ids (never by address) so that single-threaded runs repeat exactly.

namespace esdslam {

class KeyFrame;
class MapPoint;
class Map;

struct KeyFrameIdLess {
  bool operator()(const KeyFrame* a, const KeyFrame* b) const;
};
struct MapPointIdLess {
  bool operator()(const MapPoint* a, const MapPoint* b) const;
};

}  // namespace esdslam
