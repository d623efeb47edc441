// The glTF 2.0 metallic-roughness BSDF (glTF 2.0 spec, appendix B) with KHR_materials_specular,
// _ior, _transmission and _volume.
//
// Structure. Expanding the spec's fresnel_mix (KHR_materials_specular) over the transmission mix
// (KHR_materials_transmission) gives
//     f = metallic * metal + (1 - metallic) * [(1 - t) * opaque + t * glass]
//     metal  = Schlick(baseColor) * GGX reflection
//     opaque = s F * GGX reflection + Kelemen-coupled Lambertian (baseColor)
//     glass  = s F * GGX reflection + (1 - s F) * baseColor * GGX refraction (Walter et al. 2007)
// with t = transmission and s = specular. The GGX reflection has the same shape in every term,
// so f() evaluates it once with the weighted sum of the terms' Fresnel factors. GGX is single
// scattering: at high roughness the metal and glass terms lose the energy of multiple bounces
// between microfacets (a white metal loses up to 16% at roughness 0.5, 69% at roughness 1); we
// accept it, the spec's reference BRDF being single-scattering too. The opaque term does not
// lose it, as the coupled Lambertian takes all the energy its specular layer leaves.
//
// Sides. Every query mirrors the local frame so that wo is on the +z side of the geometric
// normal. The opaque terms are then two-sided (glTF double-sided surfaces), while the glass term
// seen from the back (inside a solid) uses eta = 1 / ior, with total internal reflection
// (fresnelDielectric). Thin-walled glass is the same from both sides and does not bend light:
// its reflection is in f() and its straight transmission in straightTransmittance().
//
// Sampling, one strategy picked per sample (one-sample MIS; pdf() is the same mixture): the
// Lambertian (cosine), the GGX reflection of the metal and opaque terms (visible normals), and
// for a solid the glass term, which samples a visible normal and then reflects or refracts with
// the probability of its Fresnel reflectance, as pbrt-v4's DielectricBxDF does. Each strategy
// has a delta limit when alpha is below GgxDistribution::kSmoothAlpha.
#include "core/bsdf.h"

#include "core/fresnel.h"
#include "core/microfacet.h"
#include "core/sampling.h"
#include "core/specular_albedo.h"

namespace penumbra {
namespace {

// Strategy-selection estimates below this are raised to it, so that a strategy with a small
// estimate for this wo is still used where its lobe has a value (a zero probability would bias
// the estimate there).
constexpr float kMinLobeEstimate = 0.01f;

// Relative IORs closer to 1 than this are index-matched: refraction does not bend light, so the
// refraction lobe is a delta whatever the roughness (pbrt-v4's DielectricBxDF, eta == 1). The
// rough refraction lobe has an angular width of about alpha |1 - 1/eta|, so below 1e-3 it is
// already narrower than any mirror we keep as a lobe (GgxDistribution::kSmoothAlpha).
constexpr float kIndexMatched = 1e-3f;

// Directional albedo of the GGX reflection with Schlick Fresnel, E = F0 a + (1 - F0) b; for a
// mirror E = F(mu) exactly.
SchlickAlbedo schlickAlbedo(float cosTheta, float roughness, bool smooth) {
    return smooth ? SchlickAlbedo{1.0f, schlickWeight(cosTheta)}
                  : ggxSchlickAlbedo(cosTheta, roughness);
}

// Generalised half vector wo + eta wi (Walter et al. 2007, Eq. 16; eta = 1 gives the reflection
// half vector, Eq. 13), normalised and turned to the +z side. Nothing when it is degenerate.
std::optional<Vec3> halfVector(const Vec3& wo, const Vec3& wi, float eta) {
    const Vec3 h = wo + eta * wi;
    const float len2 = glm::dot(h, h);
    if (!(len2 > 1e-20f))
        return std::nullopt;
    return h * (std::copysign(1.0f, h.z) / std::sqrt(len2));
}

}  // namespace

Bsdf::Bsdf(const ShadingParams& params, const Frame& shading, const Vec3& ng)
    : params_(params), shading_(shading), ng_(ng) {
    // The spec's ranges; ior >= 1 (KHR_materials_ior), and index-matched ior exactly 1.
    params_.baseColor = glm::clamp(params_.baseColor, 0.0f, 1.0f);
    params_.metallic = glm::clamp(params_.metallic, 0.0f, 1.0f);
    params_.roughness = glm::clamp(params_.roughness, 0.0f, 1.0f);
    params_.specular = glm::clamp(params_.specular, 0.0f, 1.0f);
    params_.specularColor = glm::max(params_.specularColor, 0.0f);
    params_.transmission = glm::clamp(params_.transmission, 0.0f, 1.0f);
    if (!(params_.ior >= 1.0f + kIndexMatched))
        params_.ior = 1.0f;

    // The shading normal goes to the side of ng (keeping the frame right-handed).
    if (glm::dot(shading_.n, ng_) < 0.0f) {
        shading_.n = -shading_.n;
        shading_.t = -shading_.t;
    }

    alpha_ = sqr(params_.roughness);
    smooth_ = alpha_ < GgxDistribution::kSmoothAlpha;
    deltaRefraction_ = smooth_ || params_.ior == 1.0f;
    f0_ = dielectricF0(params_.ior, params_.specularColor);
    // E_avg = 2 integral E(mu) mu dmu; for a mirror E = s F(mu), whose (1 - mu)^5 part averages
    // to 2 * B(2, 6) = 1/21.
    const float s = params_.specular;
    albedoAvg_ = s <= 0.0f ? Color(0.0f)
                 : smooth_ ? s * (f0_ + (Color(1.0f) - f0_) / 21.0f)
                           : s * ggxSchlickAlbedoAverage(params_.roughness)(f0_);

    const float m = params_.metallic;
    const float t = params_.transmission;
    const bool thin = params_.thinWalled;
    const bool coloured = maxComponent(params_.baseColor) > 0.0f;
    // A thin wall's glass term only reflects (in f) and its reflection joins the GGX strategy;
    // a solid's glass term is a strategy of its own.
    hasDiffuse_ = (1.0f - m) * (1.0f - t) > 0.0f && coloured;
    hasReflection_ = m > 0.0f || (1.0f - m) * s * (thin ? 1.0f : 1.0f - t) > 0.0f;
    hasGlass_ = !thin && (1.0f - m) * t > 0.0f && (s > 0.0f || coloured);
    const uint32_t reflectionLobe = kLobeReflection | (smooth_ ? kLobeSpecular : kLobeGlossy);
    if (hasDiffuse_)
        lobes_ |= kLobeReflection | kLobeDiffuse;
    if (hasReflection_ || (hasGlass_ && s > 0.0f))
        lobes_ |= reflectionLobe;
    if (hasGlass_ && coloured) {
        lobes_ |= kLobeTransmission | (deltaRefraction_ ? kLobeSpecular : kLobeGlossy);
    }
}

Vec3 Bsdf::toLocal(const Vec3& w, bool front) const {
    const Vec3 l = shading_.toLocal(w);
    return front ? l : Vec3(l.x, l.y, -l.z);
}

Vec3 Bsdf::toWorld(const Vec3& w, bool front) const {
    return shading_.toWorld(front ? w : Vec3(w.x, w.y, -w.z));
}

// E(mu) of the dielectric specular layer per channel: s (F0 A + (1 - F0) B), exact for a mirror.
Color Bsdf::specularAlbedo(float cosTheta) const {
    if (params_.specular <= 0.0f)
        return Color(0.0f);  // no specular layer: skip the table lookup
    return params_.specular * schlickAlbedo(cosTheta, params_.roughness, smooth_)(f0_);
}

// Fresnel factor of the whole GGX reflection (or of the mirror) for a microfacet at cosine
// cosTheta to wo: the metal's Schlick(baseColor) and the dielectric's s F, where the glass term
// of a solid seen from inside has total internal reflection and the opaque term does not.
Color Bsdf::mirrorFresnel(const Query& q, float cosTheta) const {
    const float m = params_.metallic;
    const float t = params_.transmission;
    const Color opaque = fresnelSchlick(f0_, cosTheta);
    const Color glass = fresnelDielectric(f0_, cosTheta, q.eta);
    const Color dielectric = params_.specular * ((1.0f - t) * opaque + t * glass);
    return m * fresnelSchlick(params_.baseColor, cosTheta) + (1.0f - m) * dielectric;
}

// Probability that the glass strategy reflects rather than refracts, for a microfacet at
// cosine cosTheta to wo: the luminance of its reflectance s F. With an index-matched rough
// surface the refraction is a delta whose probability must not depend on the microfacet, so
// the choice uses the lobe's albedo E(mu_o) instead.
float Bsdf::glassReflectionChoice(const Query& q, float cosTheta) const {
    const Color reflectance = deltaRefraction_ && !smooth_
                                  ? q.albedo
                                  : params_.specular * fresnelDielectric(f0_, cosTheta, q.eta);
    return glm::clamp(luminance(reflectance), 0.0f, 1.0f);
}

std::optional<Bsdf::Query> Bsdf::query(const Vec3& wo) const {
    // A tracer asks f, pdf and sample for the same wo at a vertex: compute the query once.
    if (cachedQuery_ && wo == cachedWo_)
        return *cachedQuery_;
    cachedWo_ = wo;
    cachedQuery_ = computeQuery(wo);
    return *cachedQuery_;
}

std::optional<Bsdf::Query> Bsdf::computeQuery(const Vec3& wo) const {
    const float cosGeometric = glm::dot(wo, ng_);
    if (!(std::abs(cosGeometric) > 0.0f) || !std::isfinite(cosGeometric))
        return std::nullopt;
    Query q;
    q.front = cosGeometric > 0.0f;
    q.wo = toLocal(wo, q.front);
    // wo above the geometric surface but below the shading one (normal mapping): the shading
    // model has nothing to say there, so nothing scatters (as Mitsuba 3 does).
    if (q.wo.z <= 0.0f)
        return std::nullopt;
    q.eta = q.front || params_.thinWalled ? params_.ior : 1.0f / params_.ior;

    // Each strategy's share of the albedo for this wo, by luminance, selects it.
    const float mu = q.wo.z;
    const float m = params_.metallic;
    const float t = params_.transmission;
    const Color& base = params_.baseColor;
    // No specular layer and no metal (a pure Lambertian surface): skip the table lookup.
    const bool hasSpecularLayer = m > 0.0f || params_.specular > 0.0f;
    const SchlickAlbedo albedo = hasSpecularLayer ? schlickAlbedo(mu, params_.roughness, smooth_)
                                                  : SchlickAlbedo{0.0f, 0.0f};
    q.albedo = params_.specular * albedo(f0_);
    const Color metal = albedo(base);
    const float opaqueShare = params_.thinWalled ? 1.0f : 1.0f - t;
    const float diffuse = (1.0f - m) * (1.0f - t) * luminance(base * (Color(1.0f) - q.albedo));
    const float reflection = m * luminance(metal) + (1.0f - m) * opaqueShare * luminance(q.albedo);
    // The glass term reflects s F and refracts baseColor (1 - s F), F at the macro normal.
    const Color glassReflection = params_.specular * fresnelDielectric(f0_, mu, q.eta);
    const float glass =
        (1.0f - m) * t * luminance(glassReflection + base * (Color(1.0f) - glassReflection));
    q.pDiffuse = hasDiffuse_ ? glm::max(diffuse, kMinLobeEstimate) : 0.0f;
    q.pReflection = hasReflection_ ? glm::max(reflection, kMinLobeEstimate) : 0.0f;
    q.pGlass = hasGlass_ ? glm::max(glass, kMinLobeEstimate) : 0.0f;
    const float total = q.pDiffuse + q.pReflection + q.pGlass;
    if (total <= 0.0f)
        return std::nullopt;
    q.pDiffuse /= total;
    q.pReflection /= total;
    q.pGlass /= total;
    return q;
}

Color Bsdf::evalF(const Query& q, const Vec3& wiWorld, TransportMode mode, bool withMatte) const {
    const float cosGeometric = glm::dot(wiWorld, ng_);
    if (!(std::abs(cosGeometric) > 0.0f) || !std::isfinite(cosGeometric))
        return Color(0.0f);
    const bool reflection = (cosGeometric > 0.0f) == q.front;
    const Vec3 wi = toLocal(wiWorld, q.front);
    const Vec3& wo = q.wo;
    const float m = params_.metallic;
    const float t = params_.transmission;
    const Color& base = params_.baseColor;

    if (reflection) {
        // Geometrically a reflection, but below the shading horizon: no lobe covers it.
        if (wi.z <= 0.0f)
            return Color(0.0f);
        Color f(0.0f);
        if (hasDiffuse_ && withMatte) {
            // The matte term of Kelemen and Szirmay-Kalos 2001, "A Microfacet Based Coupled
            // Specular-Matte BRDF Model with Importance Sampling": the Lambertian lobe scaled by
            // the energy the specular layer leaves, (1 - E(wo)) (1 - E(wi)) / (1 - E_avg), per
            // channel. It is reciprocal, and its albedo at wo is baseColor (1 - E(wo)), so that
            // with the specular layer's E(wo) the total is at most 1.
            const Color leftI = glm::max(Color(1.0f) - specularAlbedo(wi.z), 0.0f);
            const Color leftO = glm::max(Color(1.0f) - q.albedo, 0.0f);
            Color coupling(0.0f);
            for (int c = 0; c < 3; ++c) {
                const float norm = 1.0f - albedoAvg_[c];
                if (norm > 1e-6f)
                    coupling[c] = leftO[c] * leftI[c] / norm;
            }
            f += (1.0f - m) * (1.0f - t) * base * kInvPi * coupling;
        }
        // Microfacet reflection (Walter et al. 2007, Eq. 20) with the height-correlated G2.
        const std::optional<Vec3> h = halfVector(wo, wi, 1.0f);
        const float cosO = h ? glm::dot(wo, *h) : 0.0f;
        if ((hasReflection_ || hasGlass_) && !smooth_ && cosO > 0.0f) {
            const GgxDistribution ggx(alpha_);
            const float spec = ggx.D(*h) * ggx.G2(wo, wi) / (4.0f * wo.z * wi.z);
            f += spec * mirrorFresnel(q, cosO);
        }
        return isFinite(f) ? f : Color(0.0f);
    }

    // Transmission through a solid: rough refraction only (a delta otherwise).
    if (!hasGlass_ || deltaRefraction_ || wi.z >= 0.0f)
        return Color(0.0f);
    const float eta = q.eta;
    const std::optional<Vec3> h = halfVector(wo, wi, eta);
    if (!h)
        return Color(0.0f);
    const float cosO = glm::dot(wo, *h);
    const float cosI = glm::dot(wi, *h);
    // Only microfacets facing both directions from their own sides refract between them.
    if (cosO <= 0.0f || cosI >= 0.0f)
        return Color(0.0f);
    // Fresnel at the cosine on the outer (thinner) side, the same from wo and from wi, which
    // keeps the lobe reciprocal; it equals fresnelDielectric(f0, cosO, eta).
    const Color fresnel = fresnelSchlick(f0_, q.front ? cosO : -cosI);
    const GgxDistribution ggx(alpha_);
    // Walter et al. 2007, Eq. 21, divided by eta^2 in Radiance mode (Veach 1997, "Robust Monte
    // Carlo Methods for Light Transport Simulation", section 5.2: radiance is not conserved
    // across a refraction, importance is).
    const float denom = sqr(cosO + eta * cosI);
    float btdf = ggx.D(*h) * ggx.G2(wo, wi) * cosO * -cosI / (wo.z * -wi.z * denom);
    if (mode == TransportMode::Importance)
        btdf *= eta * eta;
    const Color transmitted = Color(1.0f) - params_.specular * fresnel;
    const Color f = (1.0f - m) * t * base * transmitted * btdf;
    return isFinite(f) ? f : Color(0.0f);
}

float Bsdf::evalPdf(const Query& q, const Vec3& wiWorld) const {
    const float cosGeometric = glm::dot(wiWorld, ng_);
    if (!(std::abs(cosGeometric) > 0.0f) || !std::isfinite(cosGeometric))
        return 0.0f;
    const bool reflection = (cosGeometric > 0.0f) == q.front;
    const Vec3 wi = toLocal(wiWorld, q.front);
    const Vec3& wo = q.wo;
    const GgxDistribution ggx(alpha_);

    if (reflection) {
        if (wi.z <= 0.0f)
            return 0.0f;
        float pdf = q.pDiffuse * cosineHemispherePdf(wi.z);
        const std::optional<Vec3> h = halfVector(wo, wi, 1.0f);
        const float cosO = h ? glm::dot(wo, *h) : 0.0f;
        if (!smooth_ && cosO > 0.0f) {
            // Visible-normal density of h times the reflection Jacobian 1 / (4 wo.h) (Walter
            // et al. 2007, Eq. 14), from the GGX strategy and the glass strategy's reflections.
            const float glass = q.pGlass > 0.0f ? q.pGlass * glassReflectionChoice(q, cosO) : 0.0f;
            pdf += (q.pReflection + glass) * ggx.visibleNormalPdf(wo, *h) / (4.0f * cosO);
        }
        return std::isfinite(pdf) ? pdf : 0.0f;
    }

    if (q.pGlass <= 0.0f || deltaRefraction_ || wi.z >= 0.0f)
        return 0.0f;
    const float eta = q.eta;
    const std::optional<Vec3> h = halfVector(wo, wi, eta);
    if (!h)
        return 0.0f;
    const float cosO = glm::dot(wo, *h);
    const float cosI = glm::dot(wi, *h);
    if (cosO <= 0.0f || cosI >= 0.0f)
        return 0.0f;
    // Refraction Jacobian |dh / dwi| = eta^2 |wi.h| / (wo.h + eta wi.h)^2 (Walter et al. 2007,
    // Eq. 17).
    const float jacobian = eta * eta * -cosI / sqr(cosO + eta * cosI);
    const float refract = 1.0f - glassReflectionChoice(q, cosO);
    const float pdf = q.pGlass * refract * ggx.visibleNormalPdf(wo, *h) * jacobian;
    return std::isfinite(pdf) ? pdf : 0.0f;
}

Color Bsdf::f(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
    const std::optional<Query> q = query(wo);
    return q ? evalF(*q, wi, mode) : Color(0.0f);
}

Color Bsdf::fGlossy(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
    const std::optional<Query> q = query(wo);
    return q ? evalF(*q, wi, mode, false) : Color(0.0f);
}

float Bsdf::pdf(const Vec3& wo, const Vec3& wi) const {
    const std::optional<Query> q = query(wo);
    return q ? evalPdf(*q, wi) : 0.0f;
}

std::optional<BsdfSample> Bsdf::sample(const Vec3& wo, float uLobe, const Vec2& u,
                                       TransportMode mode) const {
    const std::optional<Query> q = query(wo);
    if (!q)
        return std::nullopt;
    const float mu = q->wo.z;
    // Whether the geometric normal classes a world direction as a reflection (or not).
    const auto hasClass = [&](const Vec3& w, bool reflection) {
        const float cosGeometric = glm::dot(w, ng_);
        return cosGeometric != 0.0f && ((cosGeometric > 0.0f) == q->front) == reflection;
    };
    // The mirror direction, reached by the GGX strategy and by the glass one: its probability is
    // the sum of both, and f = F / |cos| so that f |cos| / pdf is the Fresnel weight.
    const auto mirror = [&]() -> std::optional<BsdfSample> {
        BsdfSample s;
        s.wi = toWorld(Vec3(-q->wo.x, -q->wo.y, q->wo.z), q->front);
        if (!hasClass(s.wi, true))
            return std::nullopt;
        s.f = mirrorFresnel(*q, mu) / mu;
        s.pdf = q->pReflection + q->pGlass * glassReflectionChoice(*q, mu);
        s.lobe = kLobeReflection | kLobeSpecular;
        return s;
    };

    BsdfSample s;
    Vec3 wi;
    if (uLobe < q->pDiffuse) {
        wi = sampleCosineHemisphere(u);
        s.lobe = kLobeReflection | kLobeDiffuse;
    } else if (uLobe < q->pDiffuse + q->pReflection) {
        if (smooth_)
            return mirror();
        const GgxDistribution ggx(alpha_);
        wi = reflect(q->wo, ggx.sampleVisibleNormal(q->wo, u));
        s.lobe = kLobeReflection | kLobeGlossy;
    } else {
        if (q->pGlass <= 0.0f)
            return std::nullopt;
        // The glass strategy: reuse the rest of uLobe to choose between reflection and
        // refraction (pbrt-v4's DielectricBxDF::Sample_f).
        const float uChoice =
            glm::min((uLobe - q->pDiffuse - q->pReflection) / q->pGlass, 0.99999994f);
        const GgxDistribution ggx(alpha_);
        const Vec3 h = smooth_ ? Vec3(0, 0, 1) : ggx.sampleVisibleNormal(q->wo, u);
        const float cosOH = glm::dot(q->wo, h);
        if (uChoice < glassReflectionChoice(*q, cosOH)) {
            if (smooth_)
                return mirror();
            wi = reflect(q->wo, h);
            s.lobe = kLobeReflection | kLobeGlossy;
        } else if (deltaRefraction_) {
            // Smooth (or index-matched) refraction. The glass term's reflection takes s F(mu)
            // (mirror) or E(mu) (rough, index-matched, so without total reflection); refraction
            // carries the rest, tinted by baseColor.
            const std::optional<Vec3> wt = refract(q->wo, Vec3(0, 0, 1), q->eta);
            if (!wt)
                return std::nullopt;
            s.wi = toWorld(*wt, q->front);
            if (!hasClass(s.wi, false))
                return std::nullopt;
            const Color reflected =
                smooth_ ? params_.specular * fresnelDielectric(f0_, mu, q->eta) : q->albedo;
            Color weight = (1.0f - params_.metallic) * params_.transmission * params_.baseColor *
                           glm::max(Color(1.0f) - reflected, 0.0f);
            if (mode == TransportMode::Radiance)
                weight /= q->eta * q->eta;
            s.f = weight / glm::max(std::abs(wt->z), 1e-7f);
            s.pdf = q->pGlass * (1.0f - glassReflectionChoice(*q, mu));
            s.lobe = kLobeTransmission | kLobeSpecular;
            s.eta = q->eta;
            return s;
        } else {
            const std::optional<Vec3> wt = refract(q->wo, h, q->eta);
            if (!wt)
                return std::nullopt;
            wi = *wt;
            s.lobe = kLobeTransmission | kLobeGlossy;
            s.eta = q->eta;
        }
    }

    // Non-delta lobes: value and density of the whole mixture, exactly as f() and pdf(). A
    // direction that the geometric normal classes differently from its lobe (possible when the
    // shading normal is tilted) is dropped, as pdf() does not count it for that lobe.
    s.wi = toWorld(wi, q->front);
    if (!hasClass(s.wi, (s.lobe & kLobeReflection) != 0))
        return std::nullopt;
    s.pdf = evalPdf(*q, s.wi);
    if (!(s.pdf > 0.0f))
        return std::nullopt;
    s.f = evalF(*q, s.wi, mode);
    if (!(maxComponent(s.f) > 0.0f))
        return std::nullopt;
    return s;
}

Color Bsdf::straightTransmittance(const Vec3& wo) const {
    if (!params_.thinWalled)
        return Color(0.0f);
    // The thin wall's glass term: what its (rough) reflection does not take, E(mu) being that
    // reflection's albedo, goes straight through, tinted by baseColor. For a mirror E = s F(mu),
    // the glTF spec's (1 - s F) weight; for a rough wall, reflection + transmission + diffuse
    // stay <= 1, as E + (1 - E) = 1.
    const float mu = glm::min(std::abs(glm::dot(wo, shading_.n)), 1.0f);
    const Color left = glm::max(Color(1.0f) - specularAlbedo(mu), 0.0f);
    return (1.0f - params_.metallic) * params_.transmission * params_.baseColor * left;
}

Color Bsdf::matteUnder(const Color& specularAlbedo) const {
    return (1.0f - params_.metallic) * (1.0f - params_.transmission) * params_.baseColor *
           glm::max(Color(1.0f) - specularAlbedo, 0.0f);
}

Color Bsdf::matteReflectance() const {
    if (!hasDiffuse_)
        return Color(0.0f);
    // Average over cosine-weighted wo of the matte albedo baseColor (1 - E(wo)): 1 - E_avg.
    return matteUnder(albedoAvg_);
}

Color Bsdf::matteAlbedo(const Vec3& wo) const {
    if (!hasDiffuse_)
        return Color(0.0f);
    const std::optional<Query> q = query(wo);
    if (!q)
        return Color(0.0f);
    // The matte term's coupling (Kelemen and Szirmay-Kalos 2001; evalF) integrated over wi:
    // (1 - E(wi)) averages to 1 - E_avg, which its normalisation cancels, leaving (1 - E(wo)).
    return matteUnder(q->albedo);
}

Color Bsdf::diffuseGlossyReflectance(bool withSharpGlossy) const {
    const float m = params_.metallic;
    Color rho = matteReflectance();
    if (smooth_)
        return rho;  // the reflection lobes are deltas
    if (!withSharpGlossy && hasSharpGlossyLobe())
        return rho;
    // The dielectric reflection has the same GGX lobe in the opaque and the glass terms; the
    // metal's Fresnel is Schlick with F0 = baseColor.
    rho += (1.0f - m) * albedoAvg_;
    if (m > 0.0f)
        rho += m * ggxSchlickAlbedoAverage(params_.roughness)(params_.baseColor);
    return rho;
}

}  // namespace penumbra
