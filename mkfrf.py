import numpy as np, json
rng = np.random.default_rng(1)
def modes_tf(s, modes, k=1.0, integr=False, zeros=()):
    H = k*np.ones_like(s)
    for f,z in modes:
        w=2*np.pi*f; H *= w**2/(s**2+2*z*w*s+w**2)
    for f,z in zeros:
        w=2*np.pi*f; H *= (s**2+2*z*w*s+w**2)/w**2
    return H
cases = {}
# A: two modes + antiresonance, 5-2000 Hz, 400 bins, 1% noise
f = np.logspace(np.log10(5), np.log10(2000), 400); s=2j*np.pi*f
cases['A'] = dict(f=f, H=modes_tf(s,[(120,0.02),(700,0.005)],zeros=[(400,0.01)]), modes=[(120,0.02),(700,0.005)], delay=0)
# B: three modes + 2 antires + delay 0.2 ms, 5-3000 Hz
f = np.logspace(np.log10(5), np.log10(3000), 500); s=2j*np.pi*f
cases['B'] = dict(f=f, H=modes_tf(s,[(80,0.03),(450,0.01),(1500,0.004)],zeros=[(300,0.02),(1100,0.01)])*np.exp(-s*2e-4), modes=[(80,0.03),(450,0.01),(1500,0.004)], delay=2e-4)
# C: four modes, delay 0.1ms, low coherence band 200-260 Hz (noisier), 2-2500 Hz linear bins 1 Hz
f = np.arange(2, 2500, 1.0); s=2j*np.pi*f
cases['C'] = dict(f=f, H=5.0*modes_tf(s,[(60,0.05),(230,0.02),(900,0.008),(1800,0.01)],zeros=[(170,0.03),(700,0.01),(1400,0.02)])*np.exp(-s*1e-4), modes=[(60,0.05),(230,0.02),(900,0.008),(1800,0.01)], delay=1e-4)
truth = {}
for name,c in cases.items():
    f,H = c['f'],c['H']
    coh = np.full(len(f), 0.98)
    noise = 0.01*np.ones(len(f))
    if name=='C':
        band=(f>200)&(f<260); coh[band]=0.3; noise[band]=0.2
    Hn = H*(1+noise*(rng.standard_normal(len(f))+1j*rng.standard_normal(len(f)))/np.sqrt(2))
    np.savetxt(f'frf_{name}.csv', np.c_[f,Hn.real,Hn.imag,coh], delimiter=',', header='freq_hz,re,im,coherence', comments='')
    np.savetxt(f'frf_{name}_polar.csv', np.c_[f,20*np.log10(abs(Hn)),np.degrees(np.angle(Hn))], delimiter=',', header='frequency,magnitude_db,phase_deg', comments='')
    np.save(f'frf_{name}_true.npy', np.c_[f,H.real,H.imag]); np.save(f'frf_{name}_noisy.npy', np.c_[f,Hn.real,Hn.imag,coh])
    truth[name]=dict(modes=c['modes'], delay=c['delay'])
json.dump(truth, open('frf_truth.json','w'), indent=1)
