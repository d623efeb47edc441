// How the parts of the hierarchical solver (radiosity_solver.h) number the ends of links: element
// sides and clusters share one int, so that links, radiance and exposure are indexed alike.
#pragma once

namespace penumbra {

// Nodes are element sides: node 2e is the front of element e, 2e + 1 its back. The patch sides,
// the roots of the trees, are nodes [0, 2 patchCount()).
inline int node(int element, bool front) {
    return 2 * element + (front ? 0 : 1);
}
inline int element(int node) {
    return node / 2;
}
inline bool front(int node) {
    return node % 2 == 0;
}
// Clusters are nodes too, with negative ids: cluster c is node -1 - c.
inline bool isCluster(int node) {
    return node < 0;
}
inline int clusterNode(int cluster) {
    return -1 - cluster;
}
inline int cluster(int node) {
    return -1 - node;
}

}  // namespace penumbra
