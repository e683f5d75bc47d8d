// The caustic buffer's two levels (splat.wgsl): the coarse level has 1/COARSE_LEVEL_FACTOR of
// the fine level's texels per axis (mirrors caustics::COARSE_LEVEL_FACTOR).
const COARSE_LEVEL_FACTOR: u32 = 8u;
