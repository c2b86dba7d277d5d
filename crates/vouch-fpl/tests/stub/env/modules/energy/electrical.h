/* vouch stub: module header named by a corpus plan's <header>; its names are in paparazzi_env.h. */
