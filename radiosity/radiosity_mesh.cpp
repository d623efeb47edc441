// The element mesh of the radiosity pass. The quadtrees and every per-element quantity live in
// RadiosityMesh's own arrays; OpenMesh holds the leaves as faces of a polygon mesh with shared
// vertices, which is what finds (or creates) the midpoint shared with a neighbour when an element
// is split, and what knows the T-vertices: a leaf next to a finer neighbour is a polygon whose
// edges carry that neighbour's midpoints.
//
// How a split works on the polygon mesh (OpenMesh's PolyConnectivity operations):
//  1. for each edge ci cj of the leaf's face, the midpoint is either on the face's boundary
//     already (a neighbour split first: it is the boundary vertex between ci and cj created on
//     the edge {ci, cj}), or created and inserted into the edge with split_edge(), which makes
//     it a T-vertex of the neighbour's face;
//  2. insert_edge() cuts each corner off the face along the segment between the two midpoints
//     next to it; the face that remains is the middle child.
// Patches are made the same way: each scene triangle is a face of the polygon mesh, split
// uniformly k times. Every vertex is created after the two end points of the edge it is the
// midpoint of, so increasing vertex ids are an order in which T-vertex values can be resolved.
#include "radiosity/radiosity_mesh.h"

#include "core/scene.h"
#include "radiosity/contact_lines.h"
#include "radiosity/quiet_openmesh_errors.h"
#include "radiosity/shadow_lines.h"
#include "radiosity/triangle_pieces.h"

#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include <algorithm>
#include <climits>
#include <cmath>
#include <iterator>
#include <optional>
#include <stdexcept>
#include <string>

namespace penumbra {

namespace {

// The edges of a child (its corners `corners` among the parent's c0 c1 c2 m01 m12 m20, as
// kChildCorners numbers them) that lie on the parent's cut edges: a child's edge lies on the
// parent's edge k when both its ends are among that edge's three points.
uint8_t childCutEdges(uint8_t parentCut, const int (&corners)[3]) {
    static constexpr int kOnParentEdge[3][3] = {{0, 3, 1}, {1, 4, 2}, {2, 5, 0}};
    const auto on = [](int k, int point) {
        return std::ranges::find(kOnParentEdge[k], point) != std::end(kOnParentEdge[k]);
    };
    uint8_t cut = 0;
    for (int c = 0; c < 3; ++c) {
        for (int k = 0; k < 3; ++k) {
            if ((parentCut >> k & 1) && on(k, corners[c]) && on(k, corners[(c + 1) % 3]))
                cut = uint8_t(cut | (1 << c));
        }
    }
    return cut;
}

using PolyMesh = OpenMesh::PolyMesh_ArrayKernelT<>;
using OpenMesh::FaceHandle;
using OpenMesh::HalfedgeHandle;
using OpenMesh::VertexHandle;

Vec3 toVec3(const PolyMesh::Point& p) {
    return {p[0], p[1], p[2]};
}

// Whether the diffuse reflectance or the emission of a material can vary over a surface.
bool rhoVaries(const Material& m) {
    return m.baseColorTexture.valid() || m.metallicRoughnessTexture.valid() ||
           m.specularTexture.valid() || m.specularColorTexture.valid();
}

// Pieces of a cut triangle smaller than this fraction of it are left out.
constexpr double kLeastPieceFraction = 1e-9;

bool emissionVaries(const Material& m) {
    return m.isEmissive() && m.emissiveTexture.valid();
}

// An element's reflectances from one BSDF evaluation: column 0 rho
// (Bsdf::diffuseGlossyReflectance(), RadiosityMesh::rho), column 1 its rough glossy lobes' part;
// a matrix, so that setMaterial's mean sums them as it sums colours.
using Reflectances = glm::mat2x3;

}  // namespace

struct RadiosityMesh::Impl {
    // rho and Le of a material whose values do not vary over the surface, evaluated once.
    struct MaterialValues {
        bool rhoVaries = false;
        bool emissionVaries = false;
        std::optional<Reflectances> rho;
        std::optional<Color> Le;
    };

    PolyMesh mesh;
    // The leaf element each face is.
    OpenMesh::FPropHandleT<int> faceElement;
    // For a vertex created as the midpoint of an edge, that edge's end points; {-1, -1} for the
    // scene's own vertices.
    OpenMesh::VPropHandleT<std::array<int, 2>> parentEdge;
    std::vector<MaterialValues> materials;

    Impl() {
        mesh.add_property(faceElement);
        mesh.add_property(parentEdge);
    }

    VertexHandle addVertex(const Vec3& p, int a = -1, int b = -1) {
        const VertexHandle v = mesh.add_vertex(PolyMesh::Point(p.x, p.y, p.z));
        mesh.property(parentEdge, v) = {a, b};
        return v;
    }

    // The halfedge of face f leaving (or reaching) vertex v. Faces are short loops: three
    // corners and the T-vertices between them.
    HalfedgeHandle halfedgeFrom(FaceHandle f, VertexHandle v) const {
        for (const HalfedgeHandle h : mesh.fh_range(f))
            if (mesh.from_vertex_handle(h) == v)
                return h;
        throw std::logic_error("radiosity mesh: vertex " + std::to_string(v.idx()) +
                               " is not on face " + std::to_string(f.idx()));
    }
    HalfedgeHandle halfedgeTo(FaceHandle f, VertexHandle v) const {
        return mesh.prev_halfedge_handle(halfedgeFrom(f, v));
    }

    bool isMidpointOf(VertexHandle v, VertexHandle a, VertexHandle b) const {
        const std::array<int, 2>& e = mesh.property(parentEdge, v);
        return (e[0] == a.idx() && e[1] == b.idx()) || (e[0] == b.idx() && e[1] == a.idx());
    }

    // The midpoint of the edge a b of face f (a before b in the face's loop): found among the
    // T-vertices between them, or created and inserted into the edge, on both of its sides.
    VertexHandle midpoint(FaceHandle f, VertexHandle a, VertexHandle b) {
        HalfedgeHandle h = halfedgeFrom(f, a);
        if (mesh.to_vertex_handle(h) == b) {
            const Vec3 p = 0.5f * (toVec3(mesh.point(a)) + toVec3(mesh.point(b)));
            const VertexHandle m = addVertex(p, a.idx(), b.idx());
            mesh.split_edge(mesh.edge_handle(h), m);
            return m;
        }
        // A neighbour split first: its midpoints of the edge and of the edge's halves (if it
        // split further) lie between a and b; one of them was created on {a, b} itself.
        for (VertexHandle v = mesh.to_vertex_handle(h); v != b;
             h = mesh.next_halfedge_handle(h), v = mesh.to_vertex_handle(h)) {
            if (isMidpointOf(v, a, b))
                return v;
        }
        throw std::logic_error("radiosity mesh: edge " + std::to_string(a.idx()) + "-" +
                               std::to_string(b.idx()) + " has T-vertices but no midpoint");
    }

    // Splits the triangular element that face f is (corners c, counter-clockwise) 1:4. Returns
    // the children's faces in the order of kChildCorners (the middle child keeps f) and sets m to
    // the midpoints m01, m12, m20.
    std::array<FaceHandle, 4> splitFace(FaceHandle f, const std::array<VertexHandle, 3>& c,
                                        std::array<VertexHandle, 3>& m) {
        for (int i = 0; i < 3; ++i)
            m[i] = midpoint(f, c[i], c[(i + 1) % 3]);
        std::array<FaceHandle, 4> children;
        children[3] = f;
        for (int i = 0; i < 3; ++i) {
            // Corner i lies between m[i - 1] (on the edge before it) and m[i] (after it):
            // insert_edge() joins m[i] to m[i - 1] and gives the loop from m[i - 1] round the
            // corner to m[i] a new face.
            const HalfedgeHandle into = halfedgeTo(f, m[i]);
            const HalfedgeHandle from = halfedgeFrom(f, m[(i + 2) % 3]);
            children[i] = mesh.face_handle(mesh.insert_edge(into, from));
        }
        return children;
    }

    // Estimate of the bytes OpenMesh holds: per vertex its point, outgoing halfedge and parent
    // edge; per halfedge its face, target vertex, next and previous halfedges; per face its
    // halfedge and element.
    size_t memoryBytes() const {
        return mesh.n_vertices() *
                   (sizeof(PolyMesh::Point) + sizeof(int) + sizeof(std::array<int, 2>)) +
               mesh.n_halfedges() * 4 * sizeof(int) + mesh.n_faces() * 2 * sizeof(int);
    }
};

RadiosityMesh::RadiosityMesh(const Scene& scene, const MeshingSettings& settings)
    : scene_(&scene), impl_(std::make_unique<Impl>()) {
    if (!(settings.patchEdgeLength > 0.0f))
        throw std::invalid_argument("radiosity mesh: patchEdgeLength must be > 0, got " +
                                    std::to_string(settings.patchEdgeLength));
    if (!(settings.minElementArea >= 0.0f))
        throw std::invalid_argument("radiosity mesh: minElementArea must be >= 0, got " +
                                    std::to_string(settings.minElementArea));
    patchEdgeLength_ = settings.patchEdgeLength;
    minElementArea_ = settings.minElementArea;
    spreadSharpGlossy_ = settings.spreadSharpGlossy;

    // One face per scene triangle (or per piece of a triangle cut along its contact lines),
    // sharing the scene mesh's vertices where the polygon mesh stays manifold. A face OpenMesh
    // refuses (a third face on an edge, a face whose winding disagrees with a neighbour's, a
    // vertex joining two closed fans) gets vertices of its own.
    struct Root {
        uint32_t mesh, triangle;
        FaceHandle face;
        std::array<VertexHandle, 3> corners;
        // The corners' barycentric coordinates in the scene triangle.
        std::array<Vec3, 3> barycentric = {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
        int piece = -1;        // index into pieces_, -1 for a whole triangle
        uint8_t cutEdges = 0;  // the piece's edges on a cut (TrianglePieces::cutEdges)
        int level = 0;
        double area;
        Vec3 normal;
    };
    std::vector<Root> roots;
    const std::span<const Mesh> meshes = scene.meshes();
    triangles_.resize(meshes.size());
    impl_->materials.resize(scene.materials().size());
    if ((settings.contactLines || settings.shadowLines) && !(minElementArea_ > 0.0f))
        throw std::invalid_argument(
            "radiosity mesh: contact or shadow lines need minElementArea > 0");
    std::optional<ContactLines> contacts;
    if (settings.contactLines)
        contacts.emplace(scene, 16.0f * minElementArea_, std::sqrt(minElementArea_));
    std::optional<ShadowLines> shadows;
    if (settings.shadowLines)
        shadows.emplace(scene, shadowSources(scene), 16.0f * minElementArea_,
                        std::sqrt(minElementArea_));
    std::vector<TriangleSegment> segments;
    // Contact features finer than an eighth of the smallest element's side are joined.
    const float contactResolution = 0.125f * std::sqrt(minElementArea_);
    uint64_t patchTotal = 0;
    const auto addRoot = [&](Root root, const std::array<Vec3, 3>& p) {
        {
            const QuietOpenMeshErrors quiet;
            root.face = impl_->mesh.add_face(root.corners[0], root.corners[1], root.corners[2]);
        }
        if (!root.face.is_valid()) {
            for (int c = 0; c < 3; ++c)
                root.corners[c] = impl_->addVertex(p[c]);
            root.face = impl_->mesh.add_face(root.corners[0], root.corners[1], root.corners[2]);
        }
        // n = 2^level patches along each edge, the smallest power of two that brings the
        // longest edge down to patchEdgeLength.
        const float longest = std::max(
            {glm::length(p[1] - p[0]), glm::length(p[2] - p[1]), glm::length(p[0] - p[2])});
        while (root.level < 30 && longest > patchEdgeLength_ * float(1 << root.level))
            ++root.level;
        patchTotal += uint64_t(1) << (2 * root.level);
        roots.push_back(root);
    };
    for (uint32_t mi = 0; mi < meshes.size(); ++mi) {
        const Mesh& mesh = meshes[mi];
        const Material& material = scene.materials()[mesh.material];
        triangles_[mi].resize(mesh.triangles.size());
        if (!holdsMaterial(material))
            continue;
        Impl::MaterialValues& values = impl_->materials[mesh.material];
        values.rhoVaries = rhoVaries(material);
        values.emissionVaries = emissionVaries(material);
        std::vector<int> shared(mesh.positions.size(), -1);
        for (uint32_t t = 0; t < mesh.triangles.size(); ++t) {
            const glm::uvec3 index = mesh.triangles[t];
            std::array<Vec3, 3> p;
            for (int c = 0; c < 3; ++c)
                p[c] = mesh.positions[index[c]];
            const glm::dvec3 cross = glm::cross(glm::dvec3(p[1] - p[0]), glm::dvec3(p[2] - p[0]));
            const double area = 0.5 * glm::length(cross);
            if (!(area > 0.0) || !std::isfinite(area))
                continue;
            Root root;
            root.mesh = mi;
            root.triangle = t;
            root.area = area;
            root.normal = Vec3(glm::normalize(cross));
            std::array<VertexHandle, 3> corners;
            for (int c = 0; c < 3; ++c) {
                int& v = shared[index[c]];
                if (v < 0)
                    v = impl_->addVertex(p[c]).idx();
                corners[c] = VertexHandle(v);
            }
            segments.clear();
            if (contacts)
                std::ranges::copy(contacts->on(mi, t), std::back_inserter(segments));
            if (shadows)
                std::ranges::copy(shadows->on(mi, t), std::back_inserter(segments));
            const TrianglePieces cut = cutTriangle(p, segments, contactResolution);
            if (cut.pieces.size() == 1) {
                root.corners = corners;
                addRoot(root, p);
                continue;
            }
            // The pieces share their vertices; the triangle's own corners are the scene's.
            const auto at = [&](const Vec3& b) { return b.x * p[0] + b.y * p[1] + b.z * p[2]; };
            std::vector<VertexHandle> points(cut.points.size());
            for (size_t i = 0; i < points.size(); ++i)
                points[i] = i < 3 ? corners[i] : impl_->addVertex(at(cut.points[i]));
            TrianglePatches& info = triangles_[mi][t];
            info.firstPiece = int(pieces_.size());
            info.pieceCount = 0;
            for (size_t pi = 0; pi < cut.pieces.size(); ++pi) {
                const std::array<uint32_t, 3>& piece = cut.pieces[pi];
                Root part = root;
                part.cutEdges = cut.cutEdges[pi];
                std::array<Vec3, 3> q;
                for (int c = 0; c < 3; ++c) {
                    part.corners[c] = points[piece[c]];
                    part.barycentric[c] = cut.points[piece[c]];
                    q[c] = at(part.barycentric[c]);
                }
                part.area =
                    0.5 * glm::length(glm::cross(glm::dvec3(q[1] - q[0]), glm::dvec3(q[2] - q[0])));
                Piece entry;
                entry.corners = part.barycentric;
                const Vec2 c0(part.barycentric[0].y, part.barycentric[0].z);
                const glm::mat2 edges(Vec2(part.barycentric[1].y, part.barycentric[1].z) - c0,
                                      Vec2(part.barycentric[2].y, part.barycentric[2].z) - c0);
                // A piece that float barycentrics flatten (features a rounding error apart that
                // cutTriangle did not join) is left out: locate() gives its points to the piece
                // beside.
                if (!(part.area > kLeastPieceFraction * area) ||
                    !(std::abs(glm::determinant(edges)) > 0.0f))
                    continue;
                entry.toPiece = glm::inverse(edges);
                part.piece = int(pieces_.size());
                pieces_.push_back(entry);
                ++info.pieceCount;
                addRoot(part, q);
            }
        }
    }
    if (patchTotal > uint64_t(INT_MAX))
        throw std::invalid_argument("radiosity mesh: patchEdgeLength " +
                                    std::to_string(patchEdgeLength_) + " m gives " +
                                    std::to_string(patchTotal) + " patches, more than 2^31 - 1");

    // Split each triangle uniformly into its patches and number them row by row of its lattice,
    // so that locate() finds a point's patch in O(1). Lattice coordinates (x, y) stand for the
    // barycentrics (1 - (x + y) / n, x / n, y / n).
    elements_.resize(size_t(patchTotal));
    patchCount_ = leafCount_ = size_t(patchTotal);
    struct PatchFace {
        FaceHandle face;
        std::array<VertexHandle, 3> corners;
        std::array<IVec2, 3> lattice;
        int level;  // splits from the scene triangle
    };
    std::vector<PatchFace> stack, patches;
    int nextPatch = 0;
    for (const Root& root : roots) {
        const int n = 1 << root.level;
        stack.assign(1, {root.face, root.corners, {IVec2(0, 0), IVec2(n, 0), IVec2(0, n)}, 0});
        patches.clear();
        while (!stack.empty()) {
            const PatchFace f = stack.back();
            stack.pop_back();
            if (f.level == root.level) {
                patches.push_back(f);
                continue;
            }
            std::array<VertexHandle, 3> m;
            const std::array<FaceHandle, 4> faces = impl_->splitFace(f.face, f.corners, m);
            const std::array<VertexHandle, 6> v = {f.corners[0], f.corners[1], f.corners[2],
                                                   m[0],         m[1],         m[2]};
            const std::array<IVec2, 6> l = {f.lattice[0],
                                            f.lattice[1],
                                            f.lattice[2],
                                            (f.lattice[0] + f.lattice[1]) / 2,
                                            (f.lattice[1] + f.lattice[2]) / 2,
                                            (f.lattice[2] + f.lattice[0]) / 2};
            for (int child = 0; child < kChildren; ++child) {
                const int* k = RadiosityMesh::kChildCorners[child];
                stack.push_back({faces[child],
                                 {v[k[0]], v[k[1]], v[k[2]]},
                                 {l[k[0]], l[k[1]], l[k[2]]},
                                 f.level + 1});
            }
        }

        TrianglePatches& info = root.piece < 0 ? triangles_[root.mesh][root.triangle]
                                               : pieces_[size_t(root.piece)].patches;
        info.firstPatch = nextPatch;
        info.level = uint8_t(root.level);
        const float invN = 1.0f / float(n);
        const float patchArea = float(root.area / (double(n) * double(n)));
        for (const PatchFace& f : patches) {
            // Canonical corner order: a lower cell (i, j) (i + 1, j) (i, j + 1) starts at the
            // corner with the smallest x + y, an upper cell (i + 1, j + 1) (i, j + 1) (i + 1, j)
            // at the largest; either is the one whose x + y differs from the other two.
            std::array<int, 3> sum;
            for (int c = 0; c < 3; ++c)
                sum[c] = f.lattice[c].x + f.lattice[c].y;
            const int first = sum[1] == sum[2] ? 0 : (sum[0] == sum[2] ? 1 : 2);
            const bool upper = sum[first] > sum[(first + 1) % 3];
            const IVec2 cell = upper ? f.lattice[first] - IVec2(1) : f.lattice[first];
            const int index = cell.y * (2 * n - cell.y) + 2 * cell.x + (upper ? 1 : 0);

            const int id = nextPatch + index;
            Element& e = elements_[size_t(id)];
            for (int c = 0; c < 3; ++c) {
                const int k = (first + c) % 3;
                const IVec2 l = f.lattice[k];
                e.vertices[c] = uint32_t(f.corners[k].idx());
                const Vec3 w(float(n - l.x - l.y) * invN, float(l.x) * invN, float(l.y) * invN);
                e.barycentric[c] = w.x * root.barycentric[0] + w.y * root.barycentric[1] +
                                   w.z * root.barycentric[2];
            }
            e.normal = root.normal;
            e.area = patchArea;
            e.mesh = root.mesh;
            e.triangle = root.triangle;
            e.patch = id;
            e.face = f.face.idx();
            e.twoSided = scene.materials()[meshes[root.mesh].material].doubleSided;
            // An edge of the patch on an edge of its piece that lies on a cut: the piece's
            // lattice corners (0, 0), (n, 0), (0, n) have its edges 0, 1, 2 on y = 0, x + y = n
            // and x = 0.
            for (int c = 0; c < 3; ++c) {
                const IVec2 a = f.lattice[(first + c) % 3], b = f.lattice[(first + c + 1) % 3];
                const bool onEdge[3] = {a.y == 0 && b.y == 0, a.x + a.y == n && b.x + b.y == n,
                                        a.x == 0 && b.x == 0};
                for (int k = 0; k < 3; ++k) {
                    if (onEdge[k] && (root.cutEdges >> k & 1))
                        e.cutEdges = uint8_t(e.cutEdges | (1 << c));
                }
            }
            impl_->mesh.property(impl_->faceElement, f.face) = id;
            setMaterial(e);
        }
        nextPatch += n * n;
    }
    syncPositions();
}

RadiosityMesh::~RadiosityMesh() = default;
RadiosityMesh::RadiosityMesh(RadiosityMesh&&) noexcept = default;
RadiosityMesh& RadiosityMesh::operator=(RadiosityMesh&&) noexcept = default;

void RadiosityMesh::syncPositions() {
    const PolyMesh& mesh = impl_->mesh;
    for (size_t v = positions_.size(); v < mesh.n_vertices(); ++v)
        positions_.push_back(toVec3(mesh.point(VertexHandle(int(v)))));
}

void RadiosityMesh::setMaterial(Element& e) {
    Impl::MaterialValues& values = impl_->materials[scene_->meshes()[e.mesh].material];
    const auto rhoAt = [&](const Vec3& b) {
        const Bsdf bsdf = scene_->bsdf(scene_->surfaceAt(e.mesh, e.triangle, b));
        const Color rho = bsdf.diffuseGlossyReflectance(spreadSharpGlossy_);
        return Reflectances(rho, rho - bsdf.matteReflectance());
    };
    const auto LeAt = [&](const Vec3& b) {
        return scene_->emitted(scene_->surfaceAt(e.mesh, e.triangle, b), e.normal);
    };
    // Where a value varies, the mean over the centroid and the midpoints between it and each
    // corner: a degree-1 rule exact for a linear variation, enough for an albedo or emission
    // texture averaged per element.
    const Vec3 centroid = (e.barycentric[0] + e.barycentric[1] + e.barycentric[2]) / 3.0f;
    const auto mean = [&](const auto& valueAt) {
        auto sum = valueAt(centroid);
        for (const Vec3& corner : e.barycentric)
            sum += valueAt(0.5f * (centroid + corner));
        return 0.25f * sum;
    };
    Reflectances rho;
    if (values.rhoVaries) {
        rho = mean(rhoAt);
    } else {
        if (!values.rho)
            values.rho = rhoAt(centroid);
        rho = *values.rho;
    }
    e.rho = rho[0];
    e.rhoGlossy = rho[1];
    if (values.emissionVaries) {
        e.Le = mean(LeAt);
    } else {
        if (!values.Le)
            values.Le = LeAt(centroid);
        e.Le = *values.Le;
    }
}

int RadiosityMesh::split(int element, float minChildArea) {
    if (element < 0 || size_t(element) >= elements_.size())
        throw std::out_of_range("radiosity mesh: no element " + std::to_string(element));
    if (!isLeaf(element))
        return firstChild(element);
    if (!canSplit(element, minChildArea))
        throw std::logic_error("radiosity mesh: element " + std::to_string(element) +
                               " is too small to split (area " + std::to_string(area(element)) +
                               " m², minimum child area " + std::to_string(minChildArea) + " m²)");
    if (elements_.size() > size_t(INT_MAX) - kChildren)
        throw std::length_error("radiosity mesh: more than 2^31 - 1 elements");

    const Element parent = elements_[size_t(element)];
    std::array<VertexHandle, 3> c, m;
    for (int i = 0; i < 3; ++i)
        c[i] = VertexHandle(int(parent.vertices[i]));
    const std::array<FaceHandle, 4> faces = impl_->splitFace(FaceHandle(parent.face), c, m);
    syncPositions();

    const std::array<uint32_t, 6> v = {parent.vertices[0],   parent.vertices[1],
                                       parent.vertices[2],   uint32_t(m[0].idx()),
                                       uint32_t(m[1].idx()), uint32_t(m[2].idx())};
    const std::array<Vec3, 3>& pb = parent.barycentric;
    // Midpoints of dyadic fractions: exact.
    const std::array<Vec3, 6> b = {pb[0],
                                   pb[1],
                                   pb[2],
                                   0.5f * (pb[0] + pb[1]),
                                   0.5f * (pb[1] + pb[2]),
                                   0.5f * (pb[2] + pb[0])};
    const int first = int(elements_.size());
    for (int child = 0; child < kChildren; ++child) {
        Element e;
        for (int corner = 0; corner < 3; ++corner) {
            e.vertices[corner] = v[RadiosityMesh::kChildCorners[child][corner]];
            e.barycentric[corner] = b[RadiosityMesh::kChildCorners[child][corner]];
        }
        e.normal = parent.normal;
        e.area = 0.25f * parent.area;  // exact, and the children's areas sum to the parent's
        e.mesh = parent.mesh;
        e.triangle = parent.triangle;
        e.parent = element;
        e.patch = parent.patch;
        e.face = faces[child].idx();
        e.level = uint8_t(parent.level + 1);
        e.twoSided = parent.twoSided;
        e.cutEdges = childCutEdges(parent.cutEdges, RadiosityMesh::kChildCorners[child]);
        setMaterial(e);
        impl_->mesh.property(impl_->faceElement, faces[child]) = first + child;
        elements_.push_back(e);
    }
    elements_[size_t(element)].firstChild = first;
    elements_[size_t(element)].face = -1;
    leafCount_ += kChildren - 1;
    return first;
}

std::vector<int> RadiosityMesh::leafElements() const {
    std::vector<int> leaves;
    for (size_t e = 0; e < elementCount(); ++e) {
        if (isLeaf(static_cast<int>(e)))
            leaves.push_back(static_cast<int>(e));
    }
    return leaves;
}

std::vector<uint32_t> RadiosityMesh::leafBoundary(int element) const {
    const Element& e = at(element);
    if (e.face < 0)
        throw std::logic_error("radiosity mesh: element " + std::to_string(element) +
                               " is not a leaf");
    const PolyMesh& mesh = impl_->mesh;
    const HalfedgeHandle start =
        impl_->halfedgeFrom(FaceHandle(e.face), VertexHandle(int(e.vertices[0])));
    std::vector<uint32_t> boundary;
    HalfedgeHandle h = start;
    do {
        boundary.push_back(uint32_t(mesh.from_vertex_handle(h).idx()));
        h = mesh.next_halfedge_handle(h);
    } while (h != start);
    return boundary;
}

ElementPoint RadiosityMesh::locate(uint32_t mesh, uint32_t triangle, const Vec3& b) const {
    if (mesh >= triangles_.size() || triangle >= triangles_[mesh].size())
        throw std::out_of_range("radiosity mesh: no triangle " + std::to_string(triangle) +
                                " in mesh " + std::to_string(mesh));
    const TrianglePatches& info = triangles_[mesh][triangle];
    if (info.pieceCount == 0)
        return locateInLattice(info, b.y, b.z);
    // A cut triangle: the piece in which the point lies deepest (on an edge between pieces,
    // either; outside all of them by rounding, the nearest).
    const Vec2 point(b.y, b.z);
    const Piece* best = nullptr;
    Vec2 bestW(0.0f);
    float bestDepth = -INFINITY;
    for (int i = 0; i < info.pieceCount; ++i) {
        const Piece& piece = pieces_[size_t(info.firstPiece + i)];
        const Vec2 w = piece.toPiece * (point - Vec2(piece.corners[0].y, piece.corners[0].z));
        const float depth = std::min({1.0f - w.x - w.y, w.x, w.y});
        if (depth > bestDepth) {
            bestDepth = depth;
            best = &piece;
            bestW = w;
        }
    }
    return locateInLattice(best->patches, bestW.x, bestW.y);
}

ElementPoint RadiosityMesh::locateInLattice(const TrianglePatches& info, float b1, float b2) const {
    if (info.firstPatch < 0)
        return {};
    // Clamp into the triangle (NaN counts as 0).
    b1 = b1 > 0.0f ? std::min(b1, 1.0f) : 0.0f;
    b2 = b2 > 0.0f ? std::min(b2, 1.0f) : 0.0f;
    if (b1 + b2 > 1.0f) {
        const float s = b1 + b2;
        b1 /= s;
        b2 /= s;
    }
    // The lattice cell and its lower (i, j) (i + 1, j) (i, j + 1) or upper (i + 1, j + 1)
    // (i, j + 1) (i + 1, j) triangle, as numbered by the constructor.
    const int n = 1 << info.level;
    const float u = b1 * float(n), v = b2 * float(n);
    const int i = std::min(int(u), n - 1);
    const int j = std::min(int(v), n - 1 - i);
    const float fu = u - float(i), fv = v - float(j);
    const bool upper = fu + fv > 1.0f && i + j < n - 1;
    Vec3 w = upper ? Vec3(fu + fv - 1.0f, 1.0f - fu, 1.0f - fv) : Vec3(1.0f - fu - fv, fu, fv);
    if (w.x < 0.0f || w.y < 0.0f || w.z < 0.0f) {  // rounding at the triangle's boundary
        w = glm::max(w, Vec3(0.0f));
        w /= w.x + w.y + w.z;
    }
    int e = info.firstPatch + j * (2 * n - j) + 2 * i + (upper ? 1 : 0);

    // Down the quadtree: in the parent's weights w, child c < 3 holds the points with w[c] >= 1/2
    // and the middle child the rest; the weights in the child follow from the midpoints'.
    while (!isLeaf(e)) {
        const int child = w.x >= 0.5f ? 0 : (w.y >= 0.5f ? 1 : (w.z >= 0.5f ? 2 : 3));
        if (child == 3) {
            w = Vec3(1.0f) - 2.0f * w;
        } else {
            w *= 2.0f;
            w[child] -= 1.0f;
        }
        e = firstChild(e) + child;
    }
    return {e, w};
}

void RadiosityMesh::setElementValues(std::span<const Color> perElement,
                                     std::span<const std::array<Color, 3>> perCorner,
                                     std::span<const float> weights) {
    if (perElement.size() != elements_.size() ||
        (!perCorner.empty() && perCorner.size() != elements_.size()) ||
        (!weights.empty() && weights.size() != elements_.size()))
        throw std::invalid_argument("radiosity mesh: setElementValues got " +
                                    std::to_string(perElement.size()) + " values, " +
                                    std::to_string(perCorner.size()) + " corner values and " +
                                    std::to_string(weights.size()) + " weights for " +
                                    std::to_string(elements_.size()) + " elements");
    elementValues_.assign(perElement.begin(), perElement.end());
    const auto weight = [&](size_t e) {
        return weights.empty() ? double(elements_[e].area) : double(weights[e]);
    };

    // Nodal averaging: the weighted mean of the leaves around each vertex (the area-weighted one
    // where they all weigh 0), in double so that a constant field gives the constant exactly.
    std::vector<glm::dvec3> sum(positions_.size(), glm::dvec3(0.0));
    std::vector<double> total(positions_.size(), 0.0);
    std::vector<glm::dvec3> areaSum(positions_.size(), glm::dvec3(0.0));
    std::vector<double> areaTotal(positions_.size(), 0.0);
    for (size_t e = 0; e < elements_.size(); ++e) {
        const Element& element = elements_[e];
        if (element.firstChild >= 0)
            continue;
        for (size_t k = 0; k < 3; ++k) {
            const uint32_t v = element.vertices[k];
            const Color value = perCorner.empty() ? perElement[e] : perElement[e] + perCorner[e][k];
            sum[v] += weight(e) * glm::dvec3(value);
            total[v] += weight(e);
            areaSum[v] += double(element.area) * glm::dvec3(value);
            areaTotal[v] += element.area;
        }
    }
    vertexValues_.resize(positions_.size());
    for (size_t v = 0; v < positions_.size(); ++v) {
        vertexValues_[v] = total[v] > 0.0       ? Color(sum[v] / total[v])
                           : areaTotal[v] > 0.0 ? Color(areaSum[v] / areaTotal[v])
                                                : Color(0.0f);
    }

    // T-vertices: the vertices on a leaf's boundary that are not its corners. Each takes the mean
    // of the end points of the edge it is the midpoint of, which are either the leaf's corners or
    // T-vertices on the same leaf edge with smaller ids, so that in increasing id order the values
    // along the leaf edge come out linear between its corners (Baum et al. 1991's anchoring).
    const PolyMesh& mesh = impl_->mesh;
    std::vector<uint32_t> tVertices;
    for (size_t e = 0; e < elements_.size(); ++e) {
        const Element& element = elements_[e];
        if (element.face < 0 || (!weights.empty() && !(weights[e] > 0.0f)))
            continue;
        for (const VertexHandle v : mesh.fv_range(FaceHandle(element.face))) {
            const uint32_t id = uint32_t(v.idx());
            if (id != element.vertices[0] && id != element.vertices[1] && id != element.vertices[2])
                tVertices.push_back(id);
        }
    }
    std::sort(tVertices.begin(), tVertices.end());
    tVertices.erase(std::unique(tVertices.begin(), tVertices.end()), tVertices.end());
    for (const uint32_t v : tVertices) {
        const std::array<int, 2>& edge = mesh.property(impl_->parentEdge, VertexHandle(int(v)));
        vertexValues_[v] = 0.5f * (vertexValues_[size_t(edge[0])] + vertexValues_[size_t(edge[1])]);
    }
    tVertexCount_ = tVertices.size();
}

void RadiosityMesh::checkValuesCurrent() const {
    if (elementValues_.size() != elements_.size())
        throw std::logic_error(
            "radiosity mesh: setElementValues() must be called after the last split");
}

Color RadiosityMesh::vertexValue(uint32_t vertex) const {
    checkValuesCurrent();
    assert(vertex < vertexValues_.size());
    return vertexValues_[vertex];
}

Color RadiosityMesh::interpolate(uint32_t mesh, uint32_t triangle, const Vec3& b) const {
    checkValuesCurrent();
    const ElementPoint p = locate(mesh, triangle, b);
    if (p.element < 0)
        return Color(0.0f);
    const std::array<uint32_t, 3>& v = vertices(p.element);
    // In the form c0 + w1 (c1 - c0) + w2 (c2 - c0), a constant field comes out exactly.
    const Color& c0 = vertexValues_[v[0]];
    return c0 + p.weights.y * (vertexValues_[v[1]] - c0) + p.weights.z * (vertexValues_[v[2]] - c0);
}

Color RadiosityMesh::elementValue(uint32_t mesh, uint32_t triangle, const Vec3& b) const {
    checkValuesCurrent();
    const ElementPoint p = locate(mesh, triangle, b);
    return p.element < 0 ? Color(0.0f) : elementValues_[size_t(p.element)];
}

RadiosityMeshStats RadiosityMesh::stats() const {
    RadiosityMeshStats s;
    s.patches = patchCount_;
    s.elements = elements_.size();
    s.leaves = leafCount_;
    s.vertices = positions_.size();
    s.tVertices = tVertexCount_;
    s.pieces = pieces_.size();
    size_t triangleTables = pieces_.capacity() * sizeof(Piece);
    for (const auto& t : triangles_) {
        triangleTables += t.capacity() * sizeof(TrianglePatches);
        for (const TrianglePatches& patches : t)
            s.cutTriangles += patches.pieceCount > 0 ? 1 : 0;
    }
    s.memoryBytes = impl_->memoryBytes() + elements_.capacity() * sizeof(Element) +
                    positions_.capacity() * sizeof(Vec3) +
                    (elementValues_.capacity() + vertexValues_.capacity()) * sizeof(Color) +
                    triangleTables;
    return s;
}

}  // namespace penumbra
