// Parallax occlusion mapping in the style of HDRP's core ShaderLibrary/PerPixelDisplacement.hlsl
// (Unity-Technologies/Graphics @ 50e45ca435f942aabed02e45c76bf8dd8ef0c1a0), written for pxh from
// its description: the caller defines the height callback ComputePerPixelHeightDisplacement and
// the struct PerPixelHeightDisplacementParam; heights run from 1.0 (top) to 0.0, inward only; a
// first tap at offset 0 and one a step in before the linear search (numSteps at most 256); a
// crossing when the height tapped rises above the ray; then at most three secant probes between
// the two last heights, stopping within 0.01; the last probe's offset is returned, faded out
// over the level after lodThreshold.
real2 ParallaxOcclusionMapping(real lod, real lodThreshold, int numSteps, real3 viewDirTS,
                               PerPixelHeightDisplacementParam ppdParam, out real outHeight)
{
    numSteps = min(numSteps, 256);
    real stepSize = 1.0 / (real)numSteps;

    // From the eye into the surface: the whole slab's offset, then one step's.
    real2 parallaxMaxOffsetTS = viewDirTS.xy / -viewDirTS.z;
    real2 texOffsetPerStep = stepSize * parallaxMaxOffsetTS;

    real2 texOffsetCurrent = real2(0.0, 0.0);
    real prevHeight = ComputePerPixelHeightDisplacement(texOffsetCurrent, lod, ppdParam);
    texOffsetCurrent += texOffsetPerStep;
    real currHeight = ComputePerPixelHeightDisplacement(texOffsetCurrent, lod, ppdParam);
    real rayHeight = 1.0 - stepSize;

    [loop] for (int stepIndex = 0; stepIndex < numSteps; ++stepIndex)
    {
        if (currHeight > rayHeight)
            break;
        prevHeight = currHeight;
        rayHeight -= stepSize;
        texOffsetCurrent += texOffsetPerStep;
        currHeight = ComputePerPixelHeightDisplacement(texOffsetCurrent, lod, ppdParam);
    }

    // Secant refinement between the ray heights pt0 (above) and pt1 (below).
    real pt0 = rayHeight + stepSize;
    real pt1 = rayHeight;
    real delta0 = pt0 - prevHeight;
    real delta1 = pt1 - currHeight;
    real delta;
    real2 offset;
    for (int i = 0; i < 3; ++i)
    {
        real intersectionHeight = (pt0 * delta1 - pt1 * delta0) / (delta1 - delta0);
        offset = (1 - intersectionHeight) * texOffsetPerStep * numSteps;
        currHeight = ComputePerPixelHeightDisplacement(offset, lod, ppdParam);
        delta = intersectionHeight - currHeight;
        if (abs(delta) <= 0.01)
            break;
        if (delta < 0.0)
        {
            delta1 = delta;
            pt1 = intersectionHeight;
        }
        else
        {
            delta0 = delta;
            pt0 = intersectionHeight;
        }
    }

    outHeight = currHeight;
    offset *= (1.0 - saturate(lod - lodThreshold));
    return offset;
}
