// One scene's camera and light, the same for the WebGL and the WebGPU page: an
// orthographic camera from (sin θ, 0, cos θ) whose frame the plane fills (x foreshortened
// by cos θ on the vertical axis), and the rectangular light as scenes.json places it.
export function place( THREE, light, sc, s ) {

	const th = sc.view_deg * Math.PI / 180;
	const c = Math.cos( th );
	const cam = new THREE.OrthographicCamera( - s, s, s * c, - s * c, 0.1, 100 );
	cam.position.set( 10 * Math.sin( th ), 0, 10 * c );
	cam.up.set( - c, 0, Math.sin( th ) );
	cam.lookAt( 0, 0, 0 );
	cam.updateMatrixWorld();
	light.width = sc.light.width;
	light.height = sc.light.height;
	light.position.set( ...sc.light.center );
	light.up.set( ...sc.light.up );
	light.lookAt( ...sc.light.look_at );
	light.updateMatrixWorld();
	return cam;

}
